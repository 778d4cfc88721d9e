#!/usr/bin/env bash
# Installs the Debian packages photonbridge needs, only those missing.
# Idempotent: a second run with everything present does nothing and asks no
# package server. Needs root (or sudo) only when something is missing.
set -euo pipefail

# Build and runtime: compiler tool chain, Vulkan (loader, lavapipe, validation
# layers, glslc), Embree 3, OpenEXR 3, OpenColorIO 2, tinygltf + its json, stb
# (image writing), libspng and libjpeg-turbo (texture decoding).
# Validation peers: POV-Ray 3.7, Blender 3.4 (headless exporter, Cycles) with
# numpy. clang and its runtime (libFuzzer, sanitizers) for the fuzz targets,
# Pillow for their image seeds (tests/fuzz/make_image_seeds.py);
# valgrind for the memory checks of the CPU paths. GLFW 3, Xvfb and xauth
# (xvfb-run) for `photonbridge view` and its tests. Render farms:
# node for the Flamenco job type's test, slurm-wlm and munge (and iproute2's
# ip, for the private loopback) for the one-node Slurm cluster of
# tests/farm/slurm_check.py; the packages' services are not needed (the
# test starts its own daemons in the foreground).
PKGS=(
  build-essential cmake pkg-config python3 curl
  glslc libvulkan-dev mesa-vulkan-drivers vulkan-validationlayers vulkan-tools
  libembree-dev libopenexr-dev libopencolorio-dev
  libtinygltf-dev nlohmann-json3-dev libstb-dev libspng-dev libjpeg62-turbo-dev
  povray blender python3-numpy
  clang libclang-rt-14-dev python3-pil valgrind
  libglfw3-dev xvfb xauth
  nodejs slurm-wlm munge iproute2
  libllvm19
  python3-venv libx11-6 libxext6 libxi6 libxrender1 libxfixes3 libxxf86vm1 libxkbcommon0 libsm6 libice6 libgl1 libegl1
)
# Optional extras: skipped quietly when the archive lacks them.
OPTIONAL=(python3-matplotlib chromium)

# The Khronos glTF-Validator (npm gltf-validator) for the Blender add-on's
# tests, into tools/node_modules (ignored by git). npm comes from Debian's
# npm package unless an npm is already on PATH (e.g. with another nodejs).
VALIDATOR_VERSION=2.0.0-dev.3.10
ROOT=$(cd "$(dirname "$0")/.." && pwd)
install_validator() {
  [ -f "$ROOT/tools/node_modules/gltf-validator/package.json" ] && return 0
  command -v npm >/dev/null 2>&1 || return 0
  echo "install-deps: npm install gltf-validator@$VALIDATOR_VERSION into tools/"
  npm install --no-audit --no-fund --prefix "$ROOT/tools" "gltf-validator@$VALIDATOR_VERSION" >/dev/null ||
    echo "install-deps: gltf-validator not installed (the Blender add-on's validator test will say so)" >&2
}
command -v npm >/dev/null 2>&1 || OPTIONAL+=(npm)

# Blender 4.5 LTS as a Python module (bpy, CPython 3.11, Debian's python3)
# in tools/bpy45 (ignored by git), for the add-on's Blender 4.5 tests and
# Cycles 4.5: the newest 4.5.x LTS wheel, pinned here, with the numpy the
# wheel was built against (bpy 4.5 needs numpy < 2). The X11/GL libraries
# it loads are in PKGS (no X server is needed). Required: a package index
# that no longer serves this version is an error, not a skipped test.
BPY_VERSION=4.5.15
BPY_NUMPY=1.26.4
BPY_VENV="$ROOT/tools/bpy45"
install_bpy() {
  if "$BPY_VENV/bin/python" -c "import sys, bpy; sys.exit(bpy.app.version_string.split()[0] != '$BPY_VERSION')" \
      >/dev/null 2>&1; then
    return 0
  fi
  echo "install-deps: pip install bpy==$BPY_VERSION numpy==$BPY_NUMPY into tools/bpy45"
  rm -rf "$BPY_VENV"
  /usr/bin/python3 -m venv "$BPY_VENV"
  if ! "$BPY_VENV/bin/pip" install -q --disable-pip-version-check "bpy==$BPY_VERSION" "numpy==$BPY_NUMPY"; then
    rm -rf "$BPY_VENV"
    echo "install-deps: error: could not install bpy==$BPY_VERSION (Blender 4.5 LTS) from the Python package index;" \
         "the Blender 4.5 tests need it (change BPY_VERSION in scripts/install-deps.sh to a 4.5.x the index serves)" >&2
    exit 1
  fi
  "$BPY_VENV/bin/python" -c "import bpy; print('install-deps: Blender', bpy.app.version_string, 'in tools/bpy45')"
}

# The benchmark peers, each in its own virtual environment under tools/
# (ignored by git), with Debian's python3 as for bpy: LuxCoreRender's Python
# module (pyluxcore, PATHCPU/PhotonGI and BIDIRVMCPU) in tools/luxcore and
# Mitsuba 3 with its Dr.Jit in tools/mitsuba3. Separate venvs because each
# wheel carries its own TBB/Embree and must not be imported beside the other.
# pyluxcore 2.11 does not declare NumPy, which its DefineMeshExt and the
# drivers need. Mitsuba's LLVM variants load the newest system libLLVM:
# libllvm19 in PKGS (with Debian 12's libLLVM-15 alone, llvm_ad_rgb aborts
# compiling its first kernel, "Cannot select: fminimum"); its scalar
# variants need none. Required, as bpy: a version the index no longer
# serves is an error naming the constant to change, never a skipped test.
LUXCORE_VERSION=2.11.2
LUXCORE_NUMPY=1.26.4
LUXCORE_VENV="$ROOT/tools/luxcore"
MITSUBA_VERSION=3.9.1
DRJIT_VERSION=1.5.0
MITSUBA_NUMPY=1.26.4
MITSUBA_VENV="$ROOT/tools/mitsuba3"
# NVIDIA FLIP (pip `flip-evaluator`, the image-difference metric that
# bench/run_peers.py reports beside PSNR, through validation/flip_mean.py) in its
# own venv tools/flip. Required by the peers' benchmark test
# (bench_peers_tiny): a version the index no longer serves is an error.
FLIP_VERSION=1.7
FLIP_NUMPY=1.26.4
FLIP_VENV="$ROOT/tools/flip"
# pip_venv VENV WHAT CONSTANT CHECK PACKAGES...: make VENV hold PACKAGES
# unless CHECK (python code exiting 0) already passes in it; returns 1 when
# there was nothing to do.
pip_venv() {
  local venv=$1 what=$2 constant=$3 check=$4; shift 4
  if "$venv/bin/python" -c "$check" >/dev/null 2>&1; then
    return 1
  fi
  echo "install-deps: pip install $* into tools/$(basename "$venv")"
  rm -rf "$venv"
  /usr/bin/python3 -m venv "$venv"
  if ! "$venv/bin/pip" install -q --disable-pip-version-check "$@"; then
    rm -rf "$venv"
    echo "install-deps: error: could not install $* ($what) from the Python package index;" \
         "the peer tests need it (change $constant in scripts/install-deps.sh to a version the index serves)" >&2
    exit 1
  fi
}
install_luxcore() {
  pip_venv "$LUXCORE_VENV" "LuxCoreRender 2.11" LUXCORE_VERSION \
    "import sys, importlib.metadata as m; sys.exit(m.version('pyluxcore') != '$LUXCORE_VERSION')" \
    "pyluxcore==$LUXCORE_VERSION" "numpy==$LUXCORE_NUMPY" || return 0
  echo "install-deps: pyluxcore $("$LUXCORE_VENV/bin/python" -c "import importlib.metadata as m; print(m.version('pyluxcore'))") in tools/luxcore"
}
install_mitsuba() {
  pip_venv "$MITSUBA_VENV" "Mitsuba 3" MITSUBA_VERSION \
    "import sys, importlib.metadata as m; sys.exit(m.version('mitsuba') != '$MITSUBA_VERSION' or m.version('drjit') != '$DRJIT_VERSION')" \
    "mitsuba==$MITSUBA_VERSION" "drjit==$DRJIT_VERSION" "numpy==$MITSUBA_NUMPY" || return 0
  "$MITSUBA_VENV/bin/python" -c "import mitsuba as mi, drjit as dr; print('install-deps: mitsuba', mi.__version__, 'drjit', dr.__version__, 'in tools/mitsuba3')"
}
install_flip() {
  pip_venv "$FLIP_VENV" "NVIDIA FLIP" FLIP_VERSION \
    "import sys, importlib.metadata as m; import flip_evaluator; sys.exit(m.version('flip-evaluator') != '$FLIP_VERSION')" \
    "flip-evaluator==$FLIP_VERSION" "numpy==$FLIP_NUMPY" || return 0
  echo "install-deps: flip-evaluator $("$FLIP_VENV/bin/python" -c "import importlib.metadata as m; print(m.version('flip-evaluator'))") in tools/flip"
}

# Mesa 25's lavapipe (Vulkan 1.4 with VK_KHR_acceleration_structure,
# VK_KHR_ray_query, VK_KHR_ray_tracing_pipeline) beside the system's Mesa
# 22.3, for the ray-query path and its tests: Debian bookworm-backports'
# mesa-vulkan-drivers, pinned by version and SHA-256, fetched from the
# Debian pool and unpacked with dpkg-deb -x into tools/mesa25/root (ignored
# by git); tools/mesa25/lvp_icd.x86_64.json is its ICD manifest (library
# path relative to the manifest), used only where VK_ICD_FILENAMES names it.
# The system's driver is left as it is. Dependencies: the package asks for
# libdrm2 >= 2.4.121 (Debian 12 has 2.4.114) for its hardware drivers;
# lavapipe imports 40 libdrm functions, all present in 2.4.114, which the
# check below verifies, so no newer libdrm is unpacked (the loader could not
# make lavapipe load it without LD_LIBRARY_PATH). Every other dependency
# (libLLVM-15, libxcb*, libwayland-client0, libzstd1, ...) is in Debian 12.
# Required, as bpy: a download that fails or does not match is an error.
MESA25_VERSION=25.0.7-2~bpo12+1
MESA25_DEB="mesa-vulkan-drivers_${MESA25_VERSION}_amd64.deb"
MESA25_URL="http://deb.debian.org/debian/pool/main/m/mesa/${MESA25_DEB}"
MESA25_SHA256=3899f1800424c60a05df5d6913076a526ca8fdbabec43672cd397563d1ca3263
MESA25_DIR="$ROOT/tools/mesa25"
mesa25_fail() {
  echo "install-deps: error: Mesa $MESA25_VERSION (tools/mesa25): $*;" \
       "the ray-query tests need it (change MESA25_VERSION, MESA25_URL and MESA25_SHA256 in scripts/install-deps.sh" \
       "to a bookworm-backports mesa-vulkan-drivers the Debian pool serves)" >&2
  exit 1
}
install_mesa25() {
  local icd="$MESA25_DIR/lvp_icd.x86_64.json" lib="$MESA25_DIR/root/usr/lib/x86_64-linux-gnu/libvulkan_lvp.so"
  if [ "$(cat "$MESA25_DIR/VERSION" 2>/dev/null)" = "$MESA25_VERSION" ] && [ -f "$icd" ] && [ -f "$lib" ]; then
    return 0
  fi
  [ "$(dpkg --print-architecture)" = amd64 ] || mesa25_fail "only amd64 is pinned"
  echo "install-deps: Mesa $MESA25_VERSION lavapipe into tools/mesa25"
  rm -rf "$MESA25_DIR"
  mkdir -p "$MESA25_DIR/root"
  curl -fsSL --retry 3 -o "$MESA25_DIR/$MESA25_DEB" "$MESA25_URL" || mesa25_fail "download of $MESA25_URL failed"
  echo "$MESA25_SHA256  $MESA25_DIR/$MESA25_DEB" | sha256sum -c --quiet - || mesa25_fail "$MESA25_DEB does not match its SHA-256"
  dpkg-deb -x "$MESA25_DIR/$MESA25_DEB" "$MESA25_DIR/root" || mesa25_fail "dpkg-deb -x $MESA25_DEB failed"
  rm -f "$MESA25_DIR/$MESA25_DEB"
  [ -f "$lib" ] || mesa25_fail "the package holds no libvulkan_lvp.so"
  # Shared libraries: none missing, and every libdrm function lavapipe
  # imports present in the system's libdrm (see above).
  if ldd "$lib" | grep -q 'not found'; then
    mesa25_fail "libraries missing: $(ldd "$lib" | grep 'not found' | tr -s ' \t\n' ' ')"
  fi
  local drm missing_syms
  drm=$(ldd "$lib" | awk '$1 == "libdrm.so.2" {print $3}')
  missing_syms=$(comm -23 \
    <(objdump -T "$lib" | awk '/\*UND\*/ && $NF ~ /^drm/ {print $NF}' | sort -u) \
    <(objdump -T "$drm" | awk '!/\*UND\*/ {print $NF}' | sort -u))
  [ -z "$missing_syms" ] || mesa25_fail "the system's $drm lacks $(echo $missing_syms)"
  cat > "$icd" <<EOF
{
    "file_format_version": "1.0.0",
    "ICD": {
        "library_path": "./root/usr/lib/x86_64-linux-gnu/libvulkan_lvp.so",
        "api_version": "1.4.305"
    }
}
EOF
  local summary
  summary=$(VK_ICD_FILENAMES="$icd" vulkaninfo 2>/dev/null) || mesa25_fail "vulkaninfo with $icd failed"
  for want in "Mesa ${MESA25_VERSION%%-*}" VK_KHR_acceleration_structure VK_KHR_ray_query; do
    grep -q "$want" <<<"$summary" || mesa25_fail "vulkaninfo with $icd does not show $want"
  done
  echo "$MESA25_VERSION" > "$MESA25_DIR/VERSION"
  echo "install-deps: $(grep -m1 driverInfo <<<"$summary" | sed 's/^[[:space:]]*//') in tools/mesa25"
}

missing=()
for p in "${PKGS[@]}" "${OPTIONAL[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done
if [ ${#missing[@]} -eq 0 ]; then
  install_validator
  install_bpy
  install_luxcore
  install_mitsuba
  install_mesa25
  install_flip
  echo "install-deps: all packages present"
  exit 0
fi

SUDO=""
if [ "$(id -u)" -ne 0 ]; then
  if command -v sudo >/dev/null 2>&1; then SUDO="sudo"; else
    echo "install-deps: missing packages (${missing[*]}) and not root; run: apt-get install ${missing[*]}" >&2
    exit 1
  fi
fi
echo "install-deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
# Required packages must install; optional ones are tried one by one.
req=()
for p in "${missing[@]}"; do
  case " ${OPTIONAL[*]} " in *" $p "*) ;; *) req+=("$p");; esac
done
if [ ${#req[@]} -gt 0 ]; then
  $SUDO apt-get install -y -qq --no-install-recommends "${req[@]}"
fi
for p in "${OPTIONAL[@]}"; do
  case " ${missing[*]} " in *" $p "*)
    $SUDO apt-get install -y -qq --no-install-recommends "$p" || echo "install-deps: optional $p not installed" >&2;;
  esac
done
install_validator
install_bpy
install_luxcore
install_mitsuba
install_mesa25
install_flip
echo "install-deps: done"
