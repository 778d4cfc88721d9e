#!/usr/bin/env python3
"""Writes the seed inputs of fuzz_gltf into OUT_DIR (one flat folder):

    python3 tests/fuzz/make_seeds.py OUT_DIR [--max-bytes N]

fuzz_gltf writes each input as one file (in.gltf or in.glb) next to base.bin
and tex.png from tests/corpus/valid/base, and nothing else, so a seed must
carry its buffers and images itself. From the sample scenes (samples/*/) and
the broken-file corpus (tests/corpus/{broken,valid}/*/) it writes:

  - every .gltf / .glb file as it is (NAME.gltf, NAME.glb);
  - NAME.packed.glb: the file with every resolvable external buffer and image
    moved into one GLB BIN chunk (what Blender's "glTF Binary" export makes);
  - NAME.inline.gltf: the same with the buffer as a base64 data URI (samples
    whose buffers total at most 64 KiB);
  - NAME.base.gltf: for corpus cases whose CASE.bin / tex.png are byte-equal
    to base.bin / tex.png, the file with its URIs renamed to those, so the
    broken JSON meets real buffer data.

and, for the features the loader reads or will read:

  - feature_NAME.gltf and .packed.glb: feature_seeds.py's code-made files
    (skins, morph targets, sparse accessors, texture transforms, every
    material extension, animation channels, data-URI images, the
    PHOTONBRIDGE_blender extension, ...);
  - every file in tests/fuzz/seeds/gltf/ (Blender's own exporter:
    blender_seeds.py);
  - NAME.optional.gltf: any of these whose extensionsRequired the loader
    refuses at once, with that list removed, so mutations reach the data.

Seeds over --max-bytes (default 65536, fuzz_gltf's -max_len in run.sh) are
left out: sun_atrium's 2.8 MB buffer would slow every mutation, and libFuzzer
cuts longer inputs to -max_len anyway. A conversion that does not apply (the
JSON is the broken part, a URI is missing) is skipped: the raw file is kept.
The output is a pure function of the input files."""
import base64
import json
import os
import struct
import sys

import feature_seeds

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
BASE_DIR = os.path.join(ROOT, "tests", "corpus", "valid", "base")


def read(p):
    with open(p, "rb") as f:
        return f.read()


def pad4(b, fill):
    return b + fill * ((4 - len(b) % 4) % 4)


def make_glb(doc, blob):
    js = pad4(json.dumps(doc, separators=(",", ":")).encode(), b" ")
    out = struct.pack("<II", len(js), 0x4E4F534A) + js
    if blob is not None:
        blob = pad4(blob, b"\x00")
        out += struct.pack("<II", len(blob), 0x004E4942) + blob
    return b"glTF" + struct.pack("<II", 2, 12 + len(out)) + out


def load_uri(folder, uri):
    """Bytes of a buffer/image URI, or None when it cannot be resolved here."""
    if not isinstance(uri, str):
        return None
    if uri.startswith("data:"):
        comma = uri.find(",")
        if comma < 0 or not uri[:comma].endswith(";base64"):
            return None
        try:
            return base64.b64decode(uri[comma + 1:], validate=True)
        except ValueError:
            return None
    p = os.path.normpath(os.path.join(folder, uri))
    if not p.startswith(folder + os.sep) or not os.path.isfile(p):
        return None
    return read(p)


def parse(path):
    data = read(path)
    if path.endswith(".glb"):
        return None, None  # packed already
    try:
        doc = json.loads(data)
    except (ValueError, UnicodeDecodeError, RecursionError):
        return None, None
    return (doc, data) if isinstance(doc, dict) else (None, None)


def pack(doc, folder):
    """All buffers and external images in one blob; None when not possible."""
    doc = json.loads(json.dumps(doc))
    bufs = doc.get("buffers", [])
    if not isinstance(bufs, list) or not all(isinstance(b, dict) for b in bufs):
        return None
    blob, offsets = b"", []
    for b in bufs:
        data = load_uri(folder, b.get("uri"))
        if data is None:
            return None
        offsets.append(len(blob))
        blob = pad4(blob + data, b"\x00")
    views = doc.get("bufferViews", [])
    if not isinstance(views, list):
        return None
    for v in views:
        if not isinstance(v, dict):
            return None
        bi = v.get("buffer")
        if isinstance(bi, int) and 0 <= bi < len(offsets):
            v["buffer"] = 0
            off = v.get("byteOffset", 0)
            if isinstance(off, int):
                v["byteOffset"] = off + offsets[bi]
    images = doc.get("images", [])
    for im in images if isinstance(images, list) else []:
        if not isinstance(im, dict) or "uri" not in im or str(im["uri"]).startswith("data:"):
            continue
        data = load_uri(folder, im["uri"])
        if data is None:
            return None
        views.append({"buffer": 0, "byteOffset": len(blob), "byteLength": len(data)})
        blob = pad4(blob + data, b"\x00")
        del im["uri"]
        im["bufferView"] = len(views) - 1
        im["mimeType"] = "image/jpeg" if data[:2] == b"\xff\xd8" else "image/png"
    if views:
        doc["bufferViews"] = views
    doc["buffers"] = [{"byteLength": len(blob)}] if blob else []
    if not doc["buffers"]:
        del doc["buffers"]
    return doc, blob


def inline(doc, blob):
    doc = json.loads(json.dumps(doc))
    if blob:
        doc["buffers"] = [{"byteLength": len(blob),
                           "uri": "data:application/octet-stream;base64," + base64.b64encode(blob).decode()}]
    return (json.dumps(doc, separators=(",", ":")) + "\n").encode()


def rebase(text, folder):
    """The file with URIs of byte-equal copies of base.bin / tex.png renamed."""
    base = {name: read(os.path.join(BASE_DIR, name)) for name in ("base.bin", "tex.png")}
    out, changed = text, False
    for f in sorted(os.listdir(folder)):
        p = os.path.join(folder, f)
        if not os.path.isfile(p) or f in base:
            continue
        for name, data in base.items():
            if read(p) == data:
                key = ('"%s"' % f).encode()
                if key in out:
                    out = out.replace(key, ('"%s"' % name).encode())
                    changed = True
    return out if changed else None


def main():
    args = sys.argv[1:]
    max_bytes = 65536
    if "--max-bytes" in args:
        i = args.index("--max-bytes")
        max_bytes = int(args[i + 1])
        del args[i:i + 2]
    if len(args) != 1:
        sys.exit(__doc__)
    out = args[0]
    os.makedirs(out, exist_ok=True)
    written, skipped = 0, 0

    def emit(name, data):
        nonlocal written, skipped
        if len(data) > max_bytes:
            skipped += 1
            return
        with open(os.path.join(out, name), "wb") as f:
            f.write(data)
        written += 1

    groups = [("sample", os.path.join(ROOT, "samples"), True)]
    for g in ("broken", "valid"):
        groups.append((g, os.path.join(ROOT, "tests", "corpus", g), False))
    for prefix, top, is_sample in groups:
        if not os.path.isdir(top):
            continue
        for case in sorted(os.listdir(top)):
            folder = os.path.join(top, case)
            if not os.path.isdir(folder):
                continue
            for f in sorted(os.listdir(folder)):
                if not (f.endswith(".gltf") or f.endswith(".glb")):
                    continue
                path = os.path.join(folder, f)
                stem = "%s_%s" % (prefix, os.path.splitext(f)[0])
                raw = read(path)
                emit("%s%s" % (stem, os.path.splitext(f)[1]), raw)
                doc, _ = parse(path)
                if doc is None:
                    continue
                packed = pack(doc, folder)
                if packed is not None:
                    pdoc, blob = packed
                    emit(stem + ".packed.glb", make_glb(pdoc, blob if blob else None))
                    if is_sample and len(blob) <= 65536:
                        emit(stem + ".inline.gltf", inline(pdoc, blob))
                if not is_sample:
                    rb = rebase(raw, folder)
                    if rb is not None:
                        emit(stem + ".base.gltf", rb)
    def emit_doc(stem, doc, optional_only=False):
        if not optional_only:
            emit(stem + ".gltf", (json.dumps(doc, separators=(",", ":")) + "\n").encode())
        if "extensionsRequired" in doc:
            opt = dict(doc)
            del opt["extensionsRequired"]
            emit(stem + ".optional.gltf", (json.dumps(opt, separators=(",", ":")) + "\n").encode())

    for name, doc in feature_seeds.all_docs():
        emit_doc("feature_" + name, doc)
        packed = pack(doc, ROOT)
        if packed is not None:
            emit("feature_%s.packed.glb" % name, make_glb(packed[0], packed[1] or None))
    blender_dir = os.path.join(ROOT, "tests", "fuzz", "seeds", "gltf")
    for f in sorted(os.listdir(blender_dir)) if os.path.isdir(blender_dir) else []:
        raw = read(os.path.join(blender_dir, f))
        emit(f, raw)
        doc, _ = parse(os.path.join(blender_dir, f))
        if doc is not None:
            emit_doc(os.path.splitext(f)[0], doc, optional_only=True)
    print("make_seeds: %d seeds in %s (%d over %d bytes left out)" % (written, out, skipped, max_bytes))


if __name__ == "__main__":
    main()
