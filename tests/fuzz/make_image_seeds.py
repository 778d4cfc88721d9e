#!/usr/bin/env python3
"""Writes texture files in every PNG and JPEG variant the decoders must read:
the seeds of fuzz_image, the inputs of test_image_decode (decoded pixels
against stb_image's) and of bench/image_decode.c.

    make_image_seeds.py OUT_DIR [--large] [--blender]

PNG: every colour type (grey, RGB, palette, grey+alpha, RGBA) at every bit
depth the format allows (1-16), Adam7-interlaced and not, each of the five
row filters, palettes with tRNS, grey and RGB tRNS, tiny (1x1) to 2048 px;
written here by a small encoder (Pillow writes neither interlaced nor 16-bit
RGB PNGs). JPEG (Pillow): baseline at 4:4:4 / 4:2:2 / 4:2:0, grey,
progressive, optimised Huffman tables, Adobe CMYK, low and high quality.
Content: value noise with gradients, like a photographed texture, plus flat
and checker areas. The output is a pure function of this script and
Pillow's libjpeg.

--large adds 2048 and 4096 px textures (for the benchmark; they exceed
fuzz_image's -max_len). --blender also saves textures through Blender's own
image writer (8/16-bit PNG, BW/RGB/RGBA, JPEG), when `blender` is on PATH.
"""
import os
import random
import shutil
import struct
import subprocess
import sys
import zlib

from PIL import Image


def noise_rgba(w, h, seed, alpha=True):
    """Value noise over 3 octaves, a diagonal gradient, a checker corner."""
    rnd = random.Random(seed)
    grids = []
    for cell in (32, 8, 2):
        gw, gh = w // cell + 2, h // cell + 2
        grids.append((cell, gw, [[rnd.random() for _ in range(4)] for _ in range(gw * gh)]))
    px = []
    for y in range(h):
        for x in range(w):
            v = [0.0, 0.0, 0.0, 0.0]
            amp = 0.55
            for cell, gw, g in grids:
                fx, fy = x / cell, y / cell
                ix, iy = int(fx), int(fy)
                tx, ty = fx - ix, fy - iy
                tx, ty = tx * tx * (3 - 2 * tx), ty * ty * (3 - 2 * ty)
                a, b = g[iy * gw + ix], g[iy * gw + ix + 1]
                c, d = g[(iy + 1) * gw + ix], g[(iy + 1) * gw + ix + 1]
                for k in range(4):
                    top = a[k] + (b[k] - a[k]) * tx
                    bot = c[k] + (d[k] - c[k]) * tx
                    v[k] += amp * (top + (bot - top) * ty)
                amp *= 0.5
            grad = (x + y) / max(1, w + h - 2)
            r = v[0] * 0.7 + 0.3 * grad
            g_ = v[1] * 0.7 + 0.3 * (1 - grad)
            b_ = v[2] * 0.8
            if x < w // 4 and y < h // 4:  # a checker corner: hard edges
                r = g_ = b_ = float(((x // 4) + (y // 4)) % 2)
            a_ = min(1.0, v[3] * 1.4) if alpha else 1.0
            px.append(tuple(max(0, min(255, int(round(c * 255)))) for c in (r, g_, b_, a_)))
    return px


# ---- a small PNG encoder (ISO/IEC 15948: colour types, bit depths, filters, Adam7)

CHANNELS = {0: 1, 2: 3, 3: 1, 4: 2, 6: 4}
ADAM7 = [(0, 0, 8, 8), (4, 0, 8, 8), (0, 4, 4, 8), (2, 0, 4, 4), (0, 2, 2, 4), (1, 0, 2, 2), (0, 1, 1, 2)]


def chunk(kind, data):
    return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)


def pack_row(samples, depth):
    if depth == 8:
        return bytes(samples)
    if depth == 16:
        return b"".join(struct.pack(">H", s) for s in samples)
    out, acc, n = bytearray(), 0, 0
    for s in samples:
        acc = (acc << depth) | s
        n += depth
        if n == 8:
            out.append(acc)
            acc, n = 0, 0
    if n:
        out.append(acc << (8 - n))
    return bytes(out)


def paeth(a, b, c):
    p = a + b - c
    pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
    return a if pa <= pb and pa <= pc else (b if pb <= pc else c)


def filter_rows(rows, bpp, filt):
    """rows: packed bytes per row; filt(y) chooses the filter of row y."""
    out, prev = bytearray(), bytes(len(rows[0])) if rows else b""
    for y, row in enumerate(rows):
        f = filt(y)
        line = bytearray([f])
        for i, x in enumerate(row):
            a = row[i - bpp] if i >= bpp else 0
            b = prev[i]
            c = prev[i - bpp] if i >= bpp else 0
            pred = (0, a, b, (a + b) // 2, paeth(a, b, c))[f]
            line.append((x - pred) & 0xFF)
        out += line
        prev = row
    return bytes(out)


def png(w, h, color_type, depth, sample, interlace=False, filt=lambda y: y % 5, plte=None, trns=None):
    """sample(x, y) -> tuple of CHANNELS[color_type] ints in [0, 2^depth)."""
    ch = CHANNELS[color_type]
    bpp = max(1, ch * depth // 8)
    passes = ADAM7 if interlace else [(0, 0, 1, 1)]
    data = b""
    for x0, y0, dx, dy in passes:
        xs, ys = list(range(x0, w, dx)), list(range(y0, h, dy))
        if not xs or not ys:
            continue
        rows = [pack_row([s for x in xs for s in sample(x, y)], depth) for y in ys]
        data += filter_rows(rows, bpp, filt)
    out = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, depth, color_type, 0, 0,
                                                            1 if interlace else 0))
    if plte:
        out += chunk(b"PLTE", b"".join(bytes(c) for c in plte))
    if trns is not None:
        out += chunk(b"tRNS", trns)
    return out + chunk(b"IDAT", zlib.compress(data, 9)) + chunk(b"IEND", b"")


def png_variants(out):
    w = h = 64
    px = noise_rgba(w, h, 7)
    at = lambda x, y: px[y * w + x]
    grey = lambda x, y: (at(x, y)[0] * 3 + at(x, y)[1] * 6 + at(x, y)[2]) // 10
    files = {}
    for il in (False, True):
        tag = "_adam7" if il else ""
        for depth in (1, 2, 4, 8, 16):
            m = (1 << depth) - 1
            files["grey%d%s.png" % (depth, tag)] = png(w, h, 0, depth, lambda x, y: (grey(x, y) * m // 255,), il)
        for depth in (8, 16):
            s = 257 if depth == 16 else 1
            files["rgb%d%s.png" % (depth, tag)] = png(w, h, 2, depth, lambda x, y: tuple(c * s for c in at(x, y)[:3]), il)
            files["rgba%d%s.png" % (depth, tag)] = png(w, h, 6, depth, lambda x, y: tuple(c * s for c in at(x, y)), il)
            files["greya%d%s.png" % (depth, tag)] = png(w, h, 4, depth, lambda x, y: (grey(x, y) * s, at(x, y)[3] * s), il)
        for depth in (1, 2, 4, 8):
            n = 1 << depth
            plte = [(i * 255 // (n - 1), (i * 97) % 256, 255 - i * 255 // (n - 1)) for i in range(n)]
            trns = bytes((i * 255 // (n - 1)) for i in range(n // 2))  # fewer entries than the palette
            idx = lambda x, y: (grey(x, y) * (n - 1) // 255,)
            files["palette%d%s.png" % (depth, tag)] = png(w, h, 3, depth, idx, il, plte=plte)
            files["palette%d_trns%s.png" % (depth, tag)] = png(w, h, 3, depth, idx, il, plte=plte, trns=trns)
    files["grey8_trns.png"] = png(w, h, 0, 8, lambda x, y: (grey(x, y),), trns=struct.pack(">H", 0))
    files["rgb16_trns.png"] = png(w, h, 2, 16, lambda x, y: tuple(c * 257 for c in at(x, y)[:3]),
                                  trns=struct.pack(">HHH", 0, 0, 0))
    for f in range(5):
        files["rgba8_filter%d.png" % f] = png(w, h, 6, 8, at, filt=lambda y, f=f: f)
    files["tiny_1x1.png"] = png(1, 1, 6, 8, lambda x, y: (10, 20, 30, 40))
    files["tiny_3x2_adam7.png"] = png(3, 2, 2, 8, lambda x, y: (x * 80, y * 120, 7), True)
    files["wide_257x3.png"] = png(257, 3, 2, 8, lambda x, y: (x % 256, y * 80, (x * 7) % 256))
    # Large in pixels, small in bytes: a gradient that deflate packs into a
    # few KB (fuzz_image's inputs stop at 64 KiB and 256 Kpixel).
    files["large_2048x128.png"] = png(2048, 128, 2, 8, lambda x, y: (x // 8, y * 2, 128), filt=lambda y: 2)
    big = noise_rgba(256, 256, 11)
    files["rgba8_256.png"] = png(256, 256, 6, 8, lambda x, y: big[y * 256 + x])
    for name, data in files.items():
        with open(os.path.join(out, name), "wb") as f:
            f.write(data)
    # Pillow's own writer (zlib level and filter choice of its own).
    img = Image.new("RGBA", (w, h))
    img.putdata(px)
    img.save(os.path.join(out, "pillow_rgba.png"), optimize=True)
    img.convert("P", palette=Image.ADAPTIVE, colors=64).save(os.path.join(out, "pillow_palette.png"))
    return img


def jpeg_variants(out, img, suffix="", extra=True):
    rgb = img.convert("RGB")
    rgb.save(os.path.join(out, "baseline_444%s.jpg" % suffix), quality=90, subsampling=0)
    rgb.save(os.path.join(out, "baseline_420%s.jpg" % suffix), quality=75, subsampling=2)
    rgb.save(os.path.join(out, "progressive_420%s.jpg" % suffix), quality=85, progressive=True)
    if not extra:
        return
    rgb.save(os.path.join(out, "baseline_422.jpg"), quality=80, subsampling=1)
    rgb.save(os.path.join(out, "optimized_q30.jpg"), quality=30, optimize=True)
    rgb.save(os.path.join(out, "progressive_444_q98.jpg"), quality=98, progressive=True, subsampling=0)
    img.convert("L").save(os.path.join(out, "grey.jpg"), quality=85)
    img.convert("L").save(os.path.join(out, "grey_progressive.jpg"), quality=85, progressive=True)
    img.convert("CMYK").save(os.path.join(out, "cmyk_adobe.jpg"), quality=90)
    rgb.crop((0, 0, 1, 1)).save(os.path.join(out, "tiny_1x1.jpg"), quality=90)
    rgb.crop((0, 0, 17, 9)).save(os.path.join(out, "odd_17x9_420.jpg"), quality=90, subsampling=2)
    rgb.resize((512, 512), Image.BILINEAR).save(os.path.join(out, "large_512_progressive.jpg"), quality=60,
                                                 progressive=True)


BLENDER_SCRIPT = r"""
import bpy, math, sys
out = sys.argv[sys.argv.index('--') + 1]
w = h = 64
img = bpy.data.images.new('seed', w, h, alpha=True, float_buffer=True)
px = []
for y in range(h):
    for x in range(w):
        px += [0.5 + 0.5 * math.sin(x * 0.3), 0.5 + 0.5 * math.cos(y * 0.21), (x ^ y) / 64.0, (x + y) / 128.0]
img.pixels = px
s = bpy.context.scene.render.image_settings
for name, fmt, mode, depth in [('blender_rgba8.png', 'PNG', 'RGBA', '8'), ('blender_rgb16.png', 'PNG', 'RGB', '16'),
                               ('blender_bw8.png', 'PNG', 'BW', '8'), ('blender_rgba16.png', 'PNG', 'RGBA', '16'),
                               ('blender_q90.jpg', 'JPEG', 'RGB', '8'), ('blender_bw.jpg', 'JPEG', 'BW', '8')]:
    s.file_format = fmt
    s.color_mode = mode
    if fmt == 'PNG':
        s.color_depth = depth
    else:
        s.quality = 90
    img.save_render(out + '/' + name, scene=bpy.context.scene)
"""


def blender_variants(out):
    exe = shutil.which("blender")
    if not exe:
        print("make_image_seeds: blender not found, Blender-written textures skipped", file=sys.stderr)
        return
    env = dict(os.environ)
    env["PATH"] = ":".join(p for p in env.get("PATH", "").split(":") if "pyenv" not in p)
    script = os.path.join(out, "_blender_textures.py")
    with open(script, "w") as f:
        f.write(BLENDER_SCRIPT)
    try:
        subprocess.run([exe, "-b", "--factory-startup", "-noaudio", "--python", script, "--", out], env=env,
                       stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, timeout=120, check=True)
    finally:
        os.remove(script)


def main():
    args = [a for a in sys.argv[1:] if not a.startswith("--")]
    if len(args) != 1:
        sys.exit(__doc__)
    out = args[0]
    os.makedirs(out, exist_ok=True)
    img = png_variants(out)
    jpeg_variants(out, img)
    if "--large" in sys.argv:
        for n in (2048, 4096):
            # Upscaled noise plus fine noise: compresses like a photograph.
            base = Image.new("RGBA", (128, 128))
            base.putdata(noise_rgba(128, 128, n))
            large = base.resize((n, n), Image.BICUBIC)
            grain = Image.frombytes("L", (n, n), random.Random(n).randbytes(n * n)).convert("RGBA")
            large = Image.blend(large, grain, 0.15)
            large.convert("RGB").save(os.path.join(out, "large_%d_rgb.png" % n), optimize=False)
            large.save(os.path.join(out, "large_%d_rgba.png" % n))
            jpeg_variants(out, large, suffix="_%d" % n, extra=False)
    if "--blender" in sys.argv:
        blender_variants(out)


if __name__ == "__main__":
    main()
