"""Images for test scripts with the standard library only: write_rgb
writes an uncompressed float RGB EXR from plain bytes (numpy callers pass
array.astype('<f4').tobytes()), which photonbridge and FLIP read;
read_png reads an 8-bit PNG (non-interlaced, grey, RGB or RGBA) back as
rows of bytes. Scripts in tests/ import it beside themselves."""
import struct
import zlib


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


def read_png(path):
    """(width, height, channels, rows): rows[y] a bytes of width*channels
    values."""
    with open(path, "rb") as f:
        data = f.read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        raise ValueError("%s: not a PNG" % path)
    pos, idat, ihdr = 8, b"", None
    while pos < len(data):
        n, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + n]
        if kind == b"IHDR":
            ihdr = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat += body
        pos += 12 + n
    w, h, depth, ctype, _, _, interlace = ihdr
    ch = {0: 1, 2: 3, 6: 4}.get(ctype)
    if depth != 8 or ch is None or interlace:
        raise ValueError("%s: only 8-bit grey/RGB/RGBA, non-interlaced" % path)
    raw, stride, rows, prev = zlib.decompress(idat), w * ch, [], bytearray(w * ch)
    for y in range(h):
        ftype, line = raw[y * (stride + 1)], bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for i in range(stride):
            a = line[i - ch] if i >= ch else 0
            b, c = prev[i], prev[i - ch] if i >= ch else 0
            if ftype == 1:
                line[i] = (line[i] + a) & 255
            elif ftype == 2:
                line[i] = (line[i] + b) & 255
            elif ftype == 3:
                line[i] = (line[i] + (a + b) // 2) & 255
            elif ftype == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append(bytes(line))
        prev = line
    return w, h, ch, rows
