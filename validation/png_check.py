#!/usr/bin/env python3
"""Checks that a PNG (e.g. a headless Chromium screenshot) is not blank.

    python3 validation/png_check.py SHOT.png [--min-std 10] [--min-colors 16]

Decodes 8-bit, non-interlaced greyscale/RGB/RGBA PNGs with the standard
library only, and prints the size, the standard deviation of the luma over
all pixels and the number of distinct colours. Exit 0 when the standard
deviation and the colour count reach the limits, 1 when the picture is blank
(or nearly), 2 when the file cannot be decoded.
"""
import argparse
import struct
import sys
import zlib


def decode(path):
    with open(path, "rb") as f:
        data = f.read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        raise ValueError("not a PNG")
    pos, idat, hdr = 8, [], None
    while pos < len(data):
        n, typ = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + n]
        pos += 12 + n
        if typ == b"IHDR":
            hdr = struct.unpack(">IIBBBBB", body)
        elif typ == b"IDAT":
            idat.append(body)
        elif typ == b"IEND":
            break
    w, h, depth, ctype, _, _, interlace = hdr
    chans = {0: 1, 2: 3, 4: 2, 6: 4}.get(ctype)
    if depth != 8 or chans is None or interlace:
        raise ValueError("unsupported PNG (depth %d, colour type %d, interlace %d)" % (depth, ctype, interlace))
    raw = zlib.decompress(b"".join(idat))
    stride = w * chans
    rows, prev, p = [], bytearray(stride), 0
    for _ in range(h):
        ft = raw[p]
        line = bytearray(raw[p + 1:p + 1 + stride])
        p += 1 + stride
        for i in range(stride):
            a = line[i - chans] if i >= chans else 0
            b = prev[i]
            c = prev[i - chans] if i >= chans else 0
            if ft == 1:
                line[i] = (line[i] + a) & 255
            elif ft == 2:
                line[i] = (line[i] + b) & 255
            elif ft == 3:
                line[i] = (line[i] + ((a + b) >> 1)) & 255
            elif ft == 4:
                pa, pb, pc = abs(b - c), abs(a - c), abs(a + b - 2 * c)
                pr = a if pa <= pb and pa <= pc else (b if pb <= pc else c)
                line[i] = (line[i] + pr) & 255
        rows.append(bytes(line))
        prev = line
    return w, h, chans, rows


def write_png(path, w, h, pixel):
    def chunk(t, b):
        return struct.pack(">I", len(b)) + t + b + struct.pack(">I", zlib.crc32(t + b))
    raw = b"".join(b"\0" + b"".join(bytes(pixel(x, y)) for x in range(w)) for y in range(h))
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0))
                + chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b""))


def selftest():
    """A uniform picture is blank (1), a gradient is not (0)."""
    import os
    import tempfile
    d = tempfile.mkdtemp()
    flat, grad = os.path.join(d, "flat.png"), os.path.join(d, "grad.png")
    write_png(flat, 60, 40, lambda x, y: (255, 255, 255))
    write_png(grad, 60, 40, lambda x, y: (4 * x, 6 * y, 128))
    a = main([flat])
    b = main([grad])
    os.remove(flat)
    os.remove(grad)
    os.rmdir(d)
    ok = a == 1 and b == 0
    print("png_check selftest: uniform -> %d, gradient -> %d: %s" % (a, b, "1 passed, 0 failed" if ok else "FAILED"))
    return 0 if ok else 1


def main(argv):
    if argv == ["--selftest"]:
        return selftest()
    ap = argparse.ArgumentParser(prog="png_check.py")
    ap.add_argument("png")
    ap.add_argument("--min-std", type=float, default=10.0)
    ap.add_argument("--min-colors", type=int, default=16)
    a = ap.parse_args(argv)
    try:
        w, h, chans, rows = decode(a.png)
    except (OSError, ValueError, zlib.error, TypeError, struct.error) as e:
        print("png_check: %s: %s" % (a.png, e), file=sys.stderr)
        return 2
    s = s2 = 0.0
    colors = set()
    for r in rows:
        for x in range(0, w * chans, chans):
            px = r[x:x + min(chans, 3)]
            y = (0.2126 * px[0] + 0.7152 * px[1] + 0.0722 * px[2]) if chans >= 3 else px[0]
            s += y
            s2 += y * y
            if len(colors) < 100000:
                colors.add(bytes(px))
    n = float(w * h)
    std = max(0.0, s2 / n - (s / n) ** 2) ** 0.5
    print("png_check: %s %dx%d luma mean %.2f std %.2f, %d colours" % (a.png, w, h, s / n, std, len(colors)))
    if std < a.min_std or len(colors) < a.min_colors:
        print("png_check: blank (limits: std >= %g, colours >= %d)" % (a.min_std, a.min_colors))
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
