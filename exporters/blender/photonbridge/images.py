"""Images for the glTF writer: every image a material or the world uses
becomes a file next to the .gltf (glTF URIs must stay inside the scene's
folder for photonbridge), written once per image and colour use.

- PNG and JPEG files on disk are copied byte for byte; packed PNG and JPEG
  data is written out as it is (Blender's own bytes, no re-encoding);
- anything else (other formats, generated or edited images, packed EXR) is
  read through Image.pixels with numpy and encoded here as an 8-bit PNG,
  sRGB-encoded where the glTF slot wants colour (base colour, emission) and
  the image holds linear floats, so nothing depends on Blender's image save
  operators (which change the image datablock, unsafe during a render);
- environment maps (.hdr, .exr) are copied or written as they are; a
  generated or non-HDR world image is written as PNG;
- a float image in a material (an EXR or HDR file, a generated or edited
  float image) also gets a full-precision file (float_image: the EXR/HDR
  copied, or an uncompressed half-float EXR written here), referenced from
  the glTF texture's extensions.PHOTONBRIDGE_blender.source; the 8-bit PNG
  stays the texture's source for other glTF readers. 16-bit PNGs are copied
  as they are and read at 16 bits by photonbridge.

No bpy.context and no operators: safe in RenderEngine.update()."""
import os
import re
import shutil
import struct
import zlib

import numpy as np

import bpy

PNG_MAGIC = b"\x89PNG\r\n\x1a\n"
JPEG_MAGIC = b"\xff\xd8\xff"


def png_encode(rgba8):
    """An RGBA or RGB uint8 array (rows top to bottom) as PNG bytes."""
    h, w, c = rgba8.shape
    color_type = {3: 2, 4: 6}[c]
    raw = np.empty((h, 1 + w * c), np.uint8)
    raw[:, 0] = 0  # filter: none (zlib does the work)
    raw[:, 1:] = rgba8.reshape(h, w * c)

    def chunk(tag, data):
        body = tag + data
        return struct.pack(">I", len(data)) + body + struct.pack(">I", zlib.crc32(body) & 0xFFFFFFFF)

    return (PNG_MAGIC + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, color_type, 0, 0, 0)) +
            chunk(b"IDAT", zlib.compress(raw.tobytes(), 6)) + chunk(b"IEND", b""))


def exr_encode(rgba):
    """An (h, w, 4) float array (rows top to bottom, scene-linear) as the
    bytes of an uncompressed scanline OpenEXR file with HALF channels R, G,
    B, A (OpenEXR's file layout: magic, version 2, header attributes, a
    line offset table, one scanline a chunk; channels in name order)."""
    h, w, _ = rgba.shape
    px = np.nan_to_num(np.asarray(rgba, np.float32), nan=0.0, posinf=65504.0, neginf=0.0)
    px = np.clip(px, 0.0, 65504.0).astype("<f2")

    def attr(name, kind, data):
        return name.encode() + b"\0" + kind.encode() + b"\0" + struct.pack("<i", len(data)) + data

    chl = b"".join(c.encode() + b"\0" + struct.pack("<iB3xii", 1, 0, 1, 1) for c in "ABGR") + b"\0"
    box = struct.pack("<iiii", 0, 0, w - 1, h - 1)
    header = (b"\x76\x2f\x31\x01" + struct.pack("<i", 2) + attr("channels", "chlist", chl) +
              attr("compression", "compression", b"\0") + attr("dataWindow", "box2i", box) +
              attr("displayWindow", "box2i", box) + attr("lineOrder", "lineOrder", b"\0") +
              attr("pixelAspectRatio", "float", struct.pack("<f", 1.0)) +
              attr("screenWindowCenter", "v2f", struct.pack("<ff", 0.0, 0.0)) +
              attr("screenWindowWidth", "float", struct.pack("<f", 1.0)) + b"\0")
    line = 2 * w * 4
    first = len(header) + 8 * h
    offsets = struct.pack("<%dQ" % h, *[first + y * (8 + line) for y in range(h)])
    rows = []
    for y in range(h):
        planes = b"".join(px[y, :, k].tobytes() for k in (3, 2, 1, 0))  # A, B, G, R
        rows.append(struct.pack("<ii", y, line) + planes)
    return header + offsets + b"".join(rows)


def linear_to_srgb(x):
    """IEC 61966-2-1, as photonbridge decodes it (src/scene/scene.c)."""
    x = np.clip(x, 0.0, 1.0)
    return np.where(x <= 0.0031308, 12.92 * x, 1.055 * np.power(x, 1.0 / 2.4) - 0.055)


# Colour-space names under which Cycles reads an image's values as they are
# (scene-linear Rec.709 or data): Blender 3.4's "Linear", "Non-Color" and
# "Raw", and Blender 4.x's canonical "Linear Rec.709" (4.x's alias "Linear"
# and its "Non-Color" are covered above; `colorspace_settings.name` returns
# the canonical name). Any colour space the config marks as data counts too
# (colorspace_settings.is_data).
LINEAR_COLORSPACES = frozenset(("Linear", "Non-Color", "Raw", "Linear Rec.709"))
# Blender 4.x's wide-gamut linear colour spaces: read as linear, but
# photonbridge has Rec.709 primaries only.
WIDE_GAMUT_COLORSPACES = frozenset(("Linear Rec.2020", "ACEScg"))


def linear_colorspace(image):
    """Whether `image`'s values are linear (or data) rather than sRGB-encoded."""
    cs = image.colorspace_settings
    return (cs.name in LINEAR_COLORSPACES or cs.name in WIDE_GAMUT_COLORSPACES
            or bool(getattr(cs, "is_data", False)))


def image_pixels(image):
    """(h, w, 4) float32, rows top to bottom (Blender stores them bottom up)."""
    w, h = image.size
    px = np.empty(w * h * 4, np.float32)
    image.pixels.foreach_get(px)
    return px.reshape(h, w, 4)[::-1]


def file_kind(data):
    if data.startswith(PNG_MAGIC):
        return "png"
    if data.startswith(JPEG_MAGIC):
        return "jpg"
    return None


class ImageWriter:
    """Writes images into `folder` and hands back their URIs (file names)."""

    def __init__(self, folder, warn):
        self.folder = folder
        self.warn = warn
        self.done = {}      # (image name, mode) -> uri
        self.names = set()
        self.frame = 1      # the scene frame (an image sequence's frame follows it)
        self.gamut_warned = set()

    def linear(self, image):
        """linear_colorspace(image), warning once per image whose colour
        space has primaries other than Rec.709."""
        name = image.colorspace_settings.name
        if name in WIDE_GAMUT_COLORSPACES and image.name not in self.gamut_warned:
            self.gamut_warned.add(image.name)
            self.warn("image '%s': colour space '%s': only Rec.709 primaries are supported; "
                      "its values are read as linear Rec.709" % (image.name, name))
        return linear_colorspace(image)

    def _unique(self, stem, ext):
        # Blender names a loaded image after its file ("sky.hdr"): the
        # extension is not repeated ("sky.hdr.hdr").
        if ext and stem.lower().endswith(ext.lower()) and len(stem) > len(ext):
            stem = stem[:-len(ext)]
        stem = "".join(ch if ch.isalnum() or ch in "-_." else "_" for ch in stem) or "image"
        name, i = stem + ext, 1
        while name in self.names:
            name, i = "%s_%d%s" % (stem, i, ext), i + 1
        self.names.add(name)
        return name

    def _copy(self, src, uri):
        # A source already in the export folder under its own name (an image
        # saved beside the .gltf being written) stays as it is: copying a
        # file onto itself raises SameFileError.
        dst = os.path.join(self.folder, uri)
        if os.path.exists(dst) and os.path.samefile(src, dst):
            return
        shutil.copyfile(src, dst)

    def _source_bytes(self, image):
        """The image's own PNG/JPEG bytes (packed or on disk), or None."""
        if image.packed_file is not None:
            data = bytes(image.packed_file.data)
            return data if file_kind(data) else None
        if image.source != 'FILE' or image.is_dirty:
            return None
        path = bpy.path.abspath(image.filepath, library=image.library)
        try:
            with open(path, "rb") as f:
                head = f.read(8)
        except OSError:
            return None
        return path if file_kind(head) else None

    def _magenta(self, key, warning):
        """The one-pixel magenta image Cycles renders for an image it cannot
        load (1, 0, 1, alpha 1: IMAGE_TEXTURE_MISSING_RGBA,
        intern/cycles/util/texture.h) whatever its input, colour or data; so
        does the export, so the artist sees the same hole and a comparison
        stays fair."""
        self.warn(warning)
        key_m = ("(missing)", "magenta")
        uri = self.done.get(key_m)
        if uri is None:
            uri = self._unique("missing_image", ".png")
            with open(os.path.join(self.folder, uri), "wb") as f:
                f.write(png_encode(np.array([[[255, 0, 255, 255]]], np.uint8)))
            self.done[key_m] = uri
        self.done[key] = uri
        return uri

    def _sequence_file(self, image, user):
        """The file of image sequence `image` that Cycles reads at the scene
        frame through Image Texture node image user `user`
        (BKE_image_user_frame_get: Start Frame, Frames, Offset, Cyclic; then
        the file name's last digits replaced, keeping their zero padding)."""
        path = bpy.path.abspath(image.filepath, library=image.library)
        if user is None:
            return path
        n = user.frame_duration
        f = 0
        if n > 0:
            f = self.frame - user.frame_start + 1
            if user.use_cyclic:
                f = f % n or n
            f = max(0, min(f, n)) + user.frame_offset
        folder, name = os.path.split(path)
        stem, ext = os.path.splitext(name)
        m = re.search(r"\d+(?=\D*$)", stem)
        if m:
            stem = stem[:m.start()] + "%0*d" % (len(m.group()), f) + stem[m.end():]
        return os.path.join(folder, stem + ext)

    def texture_image(self, image, color, user=None):
        """URI of `image` as a glTF texture image. color: the slot is a colour
        one (base colour, emission: sRGB in glTF); user: the Image Texture
        node's image user (an image sequence's frame)."""
        key = (image.name, "color" if color else "data")
        if image.source == 'SEQUENCE':
            # Its pixels (when loaded at all) are of whatever frame Blender
            # last showed, and its size 0 otherwise (it was written magenta
            # as if missing): the frame's own file is copied.
            path = self._sequence_file(image, user)
            key = key + (path,)
            if key in self.done:
                return self.done[key]
            try:
                with open(path, "rb") as f:
                    kind = file_kind(f.read(8))
            except OSError:
                kind = None
            if kind is None:
                return self._magenta(key, "image '%s': sequence frame file %s is not there or not a PNG or JPEG; "
                                          "rendered magenta" % (image.name, os.path.basename(path)))
            uri = self._unique(os.path.splitext(os.path.basename(path))[0], "." + kind)
            self._copy(path, uri)
            self.done[key] = uri
            return uri
        if key in self.done:
            return self.done[key]
        if image.source == 'MOVIE':
            return self._magenta(key, "image '%s': movie textures are not translated; rendered magenta" % image.name)
        if image.source == 'TILED' and len(image.tiles) > 1:
            # Image.pixels holds the first tile only; UVs on the other tiles
            # wrap onto it.
            self.warn("image '%s': UDIM tiles are not translated; only tile %d is written"
                      % (image.name, image.tiles[0].number))
        src = self._source_bytes(image)
        # PNG/JPEG bytes are usable as they are unless a float (linear) image
        # would need encoding; byte images keep their own encoding.
        if src is not None:
            if isinstance(src, str):
                with open(src, "rb") as f:
                    ext = "." + file_kind(f.read(8))
                uri = self._unique(os.path.splitext(os.path.basename(src))[0], ext)
                self._copy(src, uri)
            else:
                uri = self._unique(image.name, "." + file_kind(src))
                with open(os.path.join(self.folder, uri), "wb") as f:
                    f.write(src)
        else:
            if image.size[0] == 0 or image.size[1] == 0:
                return self._magenta(key, "image '%s': no pixels (missing file?); rendered magenta, as Cycles does"
                                     % image.name)
            px = image_pixels(image)
            rgb = px[..., :3]
            if color and (image.is_float or self.linear(image)):
                rgb = linear_to_srgb(rgb)
            out = np.concatenate([np.clip(rgb, 0, 1), np.clip(px[..., 3:4], 0, 1)], axis=2)
            rgba8 = np.round(out * 255.0).astype(np.uint8)
            uri = self._unique(image.name, ".png")
            with open(os.path.join(self.folder, uri), "wb") as f:
                f.write(png_encode(rgba8))
        self.done[key] = uri
        return uri

    def float_image(self, image):
        """URI of a full-precision copy of a float `image` for a material
        texture (scene-linear values: an EXR or HDR file as it is, otherwise a
        half-float EXR of Image.pixels), or None where the 8-bit texture file
        already holds what the image has (8- and 16-bit PNG, JPEG)."""
        if not image.is_float or image.source in ('SEQUENCE', 'MOVIE'):
            return None  # texture_image: a PNG/JPEG frame or magenta
        key = (image.name, "float")
        if key in self.done:
            return self.done[key]
        uri = None
        if self._source_bytes(image) is None:
            data, path = None, None
            if image.packed_file is not None:
                data = bytes(image.packed_file.data)
            elif image.source == 'FILE' and not image.is_dirty:
                path = bpy.path.abspath(image.filepath, library=image.library)
                try:
                    with open(path, "rb") as f:
                        data = f.read(16)
                except OSError:
                    data, path = None, None
            ext = None
            if data is not None and data.startswith(b"\x76\x2f\x31\x01"):
                ext = ".exr"
            elif data is not None and (data.startswith(b"#?RADIANCE") or data.startswith(b"#?RGBE")):
                ext = ".hdr"
            if ext and path:
                uri = self._unique(os.path.splitext(os.path.basename(path))[0], ext)
                self._copy(path, uri)
            elif ext and image.packed_file is not None:
                uri = self._unique(image.name, ext)
                with open(os.path.join(self.folder, uri), "wb") as f:
                    f.write(data)
            elif image.size[0] > 0 and image.size[1] > 0:
                uri = self._unique(image.name, ".exr")
                with open(os.path.join(self.folder, uri), "wb") as f:
                    f.write(exr_encode(image_pixels(image)))
        self.done[key] = uri
        return uri

    def composed_image(self, name, channels):
        """A new PNG from single channels: channels maps an output channel
        index (0 R .. 3 A) to (image, source channel index) or a constant in
        [0, 1]. All images must have one size. Returns its URI."""
        size = None
        for v in channels.values():
            if not isinstance(v, (int, float)):
                size = tuple(v[0].size)
        if size is None or 0 in size:
            return None
        w, h = size
        out = np.ones((h, w, 4), np.float32)
        cache = {}
        for k, v in channels.items():
            if isinstance(v, (int, float)):
                out[..., k] = v
                continue
            image, c = v
            if tuple(image.size) != size:
                self.warn("image '%s': %dx%d, not the %dx%d of the other channels it is packed with; left out"
                          % (image.name, image.size[0], image.size[1], w, h))
                return None
            if image.name not in cache:
                cache[image.name] = image_pixels(image)
            out[..., k] = cache[image.name][..., c]
        uri = self._unique(name, ".png")
        with open(os.path.join(self.folder, uri), "wb") as f:
            f.write(png_encode(np.round(np.clip(out, 0, 1) * 255.0).astype(np.uint8)))
        return uri

    def environment_image(self, image):
        """URI of a world environment map (.hdr/.exr kept as they are)."""
        key = (image.name, "environment")
        if key in self.done:
            return self.done[key]
        uri = None
        if image.packed_file is not None:
            data = bytes(image.packed_file.data)
            ext = {"png": ".png", "jpg": ".png"}.get(file_kind(data) or "", None)
            if data.startswith(b"#?RADIANCE") or data.startswith(b"#?RGBE"):
                ext = ".hdr"
            elif data.startswith(b"\x76\x2f\x31\x01"):
                ext = ".exr"
            if ext in (".hdr", ".exr") or file_kind(data) == "png":
                uri = self._unique(image.name, ext)
                with open(os.path.join(self.folder, uri), "wb") as f:
                    f.write(data)
        elif image.source == 'FILE' and not image.is_dirty:
            path = bpy.path.abspath(image.filepath, library=image.library)
            ext = os.path.splitext(path)[1].lower()
            if ext in (".hdr", ".exr", ".png") and os.path.isfile(path):
                uri = self._unique(os.path.splitext(os.path.basename(path))[0], ext)
                self._copy(path, uri)
        if uri is None:
            uri = self.texture_image(image, color=False)
        self.done[key] = uri
        return uri
