"""Images for test scripts with the standard library only: write_rgb
writes an uncompressed float RGB EXR from plain bytes (numpy callers pass
array.astype('<f4').tobytes()), which photonbridge and FLIP read, from
interpreters without an EXR module. Scripts in tests/ import it beside
themselves."""
import struct


def _attr(name, kind, data):
    return name.encode() + b"\0" + kind.encode() + b"\0" + struct.pack("<i", len(data)) + data


def write_rgb(path, width, height, r, g, b):
    """r, g, b: width*height little-endian float32 values each (bytes),
    rows top first."""
    row = 4 * width
    for plane in (r, g, b):
        if len(plane) != row * height:
            raise ValueError("plane of %d bytes for %dx%d" % (len(plane), width, height))
    chlist = b"".join(c.encode() + b"\0" + struct.pack("<iB3xii", 2, 0, 1, 1) for c in "BGR") + b"\0"
    box = struct.pack("<4i", 0, 0, width - 1, height - 1)
    header = (b"\x76\x2f\x31\x01" + struct.pack("<i", 2) +
              _attr("channels", "chlist", chlist) +
              _attr("compression", "compression", b"\0") +
              _attr("dataWindow", "box2i", box) +
              _attr("displayWindow", "box2i", box) +
              _attr("lineOrder", "lineOrder", b"\0") +
              _attr("pixelAspectRatio", "float", struct.pack("<f", 1.0)) +
              _attr("screenWindowCenter", "v2f", struct.pack("<2f", 0.0, 0.0)) +
              _attr("screenWindowWidth", "float", struct.pack("<f", 1.0)) + b"\0")
    block = 8 + 3 * row
    start = len(header) + 8 * height
    offsets = b"".join(struct.pack("<Q", start + y * block) for y in range(height))
    with open(path, "wb") as f:
        f.write(header + offsets)
        for y in range(height):
            f.write(struct.pack("<ii", y, 3 * row))
            for plane in (b, g, r):
                f.write(plane[y * row:(y + 1) * row])
