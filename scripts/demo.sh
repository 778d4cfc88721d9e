#!/usr/bin/env bash
# make demo: what photonbridge does, on one scene with global illumination and
# a caustic (samples/cornell_caustics: a glass sphere and a mirror cube in a
# Cornell box): the GPU pipeline (Vulkan compute: direct light, photon-mapped
# indirect light and caustics, A-Trous filtering) next to the Embree reference
# path tracer, both as scene-linear EXR and as PNG through Blender's Filmic
# view, and a comparison page (slider/flip, heat map, PSNR, times):
#   out/demo/index.html, out/demo/{photonbridge,reference}.{exr,png}
# About a minute on 2 cores with lavapipe (Mesa's CPU Vulkan).
# DEMO_WIDTH, DEMO_SPP, DEMO_ITERATIONS, DEMO_REF_SPP make it smaller (the
# test does) or better; DEMO_OUT puts it elsewhere.
set -euo pipefail
exe=${1:-build/photonbridge}
scene=samples/cornell_caustics/cornell_caustics.gltf
width=${DEMO_WIDTH:-320}
spp=${DEMO_SPP:-4}
iterations=${DEMO_ITERATIONS:-4}
ref_spp=${DEMO_REF_SPP:-64}
out=${DEMO_OUT:-$(pwd)/out/demo}
mkdir -p "$(dirname "$out")"

"$exe" info "$scene" --quiet
start=$(date +%s.%N)
# validate renders both, writes the EXRs, the PNGs (one OCIO view for both)
# and the page; POV-Ray and Cycles are left out here (`photonbridge validate`
# runs them too).
"$exe" validate "$scene" --out "$out" --width "$width" --spp "$spp" --ref-spp "$ref_spp" \
  --no-povray --no-cycles --render-args "--iterations $iterations --atrous-iterations 4" >"$out.log" 2>&1 || {
  echo "demo: photonbridge validate failed; its log:" >&2
  cat "$out.log" >&2
  exit 1
}
end=$(date +%s.%N)

/usr/bin/env python3 - "$out/report.json" "$start" "$end" <<'EOF'
import json, sys
r = json.load(open(sys.argv[1]))
rs = {x["name"]: x for x in r["renders"]}
p = next((p for p in r["pairs"] if p["test"] == "photonbridge" and p["reference"] == "reference"), None)
g, ref = rs.get("photonbridge", {}), rs.get("reference", {})
st = g.get("settings", {})
print()
print("demo: rendered %s at %d px" % (r["scene"], r["width"]))
# A CPU Vulkan device (lavapipe) is named as one: the GPU pipeline runs
# there much slower than on a GPU.
dev = st.get("device")
if st.get("device_type") == "cpu":
    dev = "%s (CPU Vulkan device)" % dev
print("demo:   GPU pipeline on %s (photonbridge render): %.1f s, %s photons emitted, %s stored"
      % (dev, g.get("render_s") or 0, st.get("photons_emitted"), st.get("photons_stored")))
print("demo:   Embree reference path tracer (photonbridge reference, %s spp, SPPM caustics): %.1f s"
      % (ref.get("settings", {}).get("spp"), ref.get("render_s") or 0))
if p and p.get("psnr_db") is not None:
    print("demo:   GPU against the reference: PSNR %.2f dB, SSIM %.3f" % (p["psnr_db"], p["ssim"]))
print("demo: pictures through %s" % r.get("picture_view"))
print("demo: wrote scene-linear EXRs and PNGs in %s/" % sys.argv[1].rsplit("/", 1)[0])
print("demo: open %s/index.html" % sys.argv[1].rsplit("/", 1)[0])
print("demo: took %.1f s" % (float(sys.argv[3]) - float(sys.argv[2])))
EOF
