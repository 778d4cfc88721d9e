# photonbridge: the two commands of the README.
#   make demo   install what is missing, build, render samples/cornell_box
#   make test   install, build (normal + ASan/UBSan), run the whole suite
# Other targets: build, build-asan, install-deps, clean, fuzz-quick (each
# libFuzzer target 60 s), fuzz (FUZZ_SECONDS each, default 600, at nice 19),
# blender-addon (links and enables the Blender add-on for this user).

JOBS ?= $(shell nproc)
BUILD ?= build
ASAN_BUILD ?= build-asan
FUZZ_BUILD ?= build-fuzz
FUZZ_SECONDS ?= 600
CMAKE_FLAGS ?=
# The project's own trees treat warnings as errors (CMakeLists.txt's
# PB_WERROR is off for a plain cmake build); CMAKE_FLAGS comes after, so
# CMAKE_FLAGS=-DPB_WERROR=OFF still turns it off.
WERROR ?= -DPB_WERROR=ON

.PHONY: all demo test build build-asan install-deps clean test-fast build-fuzz fuzz-quick fuzz blender-addon

all: build

install-deps:
	@bash scripts/install-deps.sh

# The generated Makefile (not CMakeCache.txt, which a failed configure also
# leaves) marks a configured tree.
$(BUILD)/Makefile:
	cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=RelWithDebInfo $(WERROR) $(CMAKE_FLAGS)

# The ASan tree takes the normal tree's compiled shaders (PB_SHADERS_FROM,
# shaders/shaders.cmake): the same SPIR-V, compiled once.
$(ASAN_BUILD)/Makefile: | $(BUILD)/Makefile
	cmake -S . -B $(ASAN_BUILD) -DCMAKE_BUILD_TYPE=Debug -DPB_SANITIZE=ON -DPB_SHADERS_FROM=$(abspath $(BUILD)) \
	  $(WERROR) $(CMAKE_FLAGS)

# The fuzz tree: clang, libFuzzer + ASan + UBSan, only the fuzz targets
# (tests/fuzz/fuzz.cmake).
$(FUZZ_BUILD)/Makefile:
	CC=clang-14 CXX=clang++-14 cmake -S . -B $(FUZZ_BUILD) -DCMAKE_BUILD_TYPE=RelWithDebInfo -DPB_FUZZ=ON $(WERROR) $(CMAKE_FLAGS)

build: install-deps $(BUILD)/Makefile
	cmake --build $(BUILD) -j $(JOBS)

build-asan: install-deps build $(ASAN_BUILD)/Makefile
	cmake --build $(ASAN_BUILD) -j $(JOBS)

build-fuzz: install-deps $(FUZZ_BUILD)/Makefile
	cmake --build $(FUZZ_BUILD) -j $(JOBS)

demo: build
	@bash scripts/demo.sh $(BUILD)/photonbridge

# The Blender add-on as the two zips Blender installs, in $(BUILD)/blender/:
# photonbridge-VERSION-extension.zip (Blender 4.2+ extension) and
# photonbridge-VERSION-addon.zip (legacy add-on, Blender 3.4 to 5.x).
.PHONY: blender-extension blender-addon-zip
blender-extension blender-addon-zip:
	python3 scripts/blender_package.py $(BUILD)/blender

# The add-on's copy of the settings table (src/render/settings.h), written
# by the binary; a test fails while the two differ.
.PHONY: settings-table
settings-table: build
	$(BUILD)/photonbridge settings --python > exporters/blender/photonbridge/settings_table.py

# The Blender render engine for this user (docs/blender.md);
# BLENDER=/path/to/blender picks the Blender (default: the one on PATH).
blender-addon: build
	@bash scripts/install-blender-addon.sh $(BUILD)/photonbridge

# The whole suite, in the normal build and again under ASan + UBSan, then
# fuzz-quick where clang can build libFuzzer programs.
test: build build-asan
	cd $(BUILD) && ctest --output-on-failure -j $(JOBS)
	cd $(ASAN_BUILD) && ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 \
	  UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
	  ctest --output-on-failure -j $(JOBS) -LE no-sanitize
	@if bash tests/fuzz/run.sh --check; then $(MAKE) --no-print-directory fuzz-quick; \
	else echo "fuzz-quick: skipped (needs clang-14 with libFuzzer: libclang-rt-14-dev)"; fi

# libFuzzer runs (tests/fuzz/run.sh): findings are kept in
# $(FUZZ_BUILD)/fuzz/crashes/TARGET/ and fail the target. fuzz-quick runs
# gltf beside exr-then-image (each libFuzzer process uses one core: on 2
# cores the same 60 s of each target in 2 minutes instead of 3); gltf's
# output follows when both are done.
fuzz-quick: build-fuzz
	@bash tests/fuzz/run.sh $(FUZZ_BUILD) 60 gltf >$(FUZZ_BUILD)/fuzz-quick-gltf.log 2>&1 & gltf=$$!; \
	bash tests/fuzz/run.sh $(FUZZ_BUILD) 60 exr image; rest=$$?; wait $$gltf; g=$$?; \
	cat $(FUZZ_BUILD)/fuzz-quick-gltf.log; test $$rest -eq 0 && test $$g -eq 0

# make fuzz [FUZZ_TARGETS="gltf exr image"] [FUZZ_SECONDS=600] [FUZZ_RUNS=N]:
# one target after another at nice $(FUZZ_NICE), each stopping after
# FUZZ_SECONDS or FUZZ_RUNS executions, whichever comes first.
FUZZ_NICE ?= 19
FUZZ_TARGETS ?=
FUZZ_RUNS ?=
fuzz: build-fuzz
	NICE=$(FUZZ_NICE) FUZZ_ARGS="$(FUZZ_ARGS)$(if $(FUZZ_RUNS), -runs=$(FUZZ_RUNS))" \
	  bash tests/fuzz/run.sh $(FUZZ_BUILD) $(FUZZ_SECONDS) $(FUZZ_TARGETS)

# The normal build's suite only.
test-fast: build
	cd $(BUILD) && ctest --output-on-failure -j $(JOBS)

clean:
	rm -rf $(BUILD) $(ASAN_BUILD) $(FUZZ_BUILD) out

# Speed against error (bench/run_bench.py, BENCHMARKS.md; results in
# bench/results/DEVICE/MODE/):
#   make bench        every renderer and sample (about half an hour on 2 cores)
#   make bench-quick  2 scenes, small images, few points (a few minutes)
# DEVICE=N renders photonbridge on Vulkan device N (photonbridge info
# --devices), e.g. an NVIDIA GPU; its results go to that device's folder.
# Debian's python3 has python3-matplotlib (the plots); another python3
# without it still writes the tables. BENCH_ARGS: more run_bench.py options.
.PHONY: bench bench-quick bench-build
BENCH_PYTHON ?= $(shell [ -x /usr/bin/python3 ] && echo /usr/bin/python3 || echo python3)
BENCH_ARGS ?=
bench-build: install-deps $(BUILD)/Makefile
	cmake --build $(BUILD) -j $(JOBS) --target photonbridge pb_bench_lbvh

bench: bench-build
	$(BENCH_PYTHON) bench/run_bench.py --exe $(BUILD)/photonbridge $(if $(DEVICE),--device $(DEVICE)) $(BENCH_ARGS)

# Animated sequences: per-frame error and flicker with the filters off,
# temporal, temporal + A-Trous, and the filters' cost at 1920x1080
# (bench/run_sequences.py; results in bench/results/DEVICE/sequences/).
.PHONY: bench-sequences
bench-sequences: install-deps $(BUILD)/Makefile
	cmake --build $(BUILD) -j $(JOBS) --target photonbridge pb_bench_filters
	$(BENCH_PYTHON) bench/run_sequences.py --exe $(BUILD)/photonbridge $(if $(DEVICE),--device $(DEVICE)) $(BENCH_ARGS)

# Soft lights and the world against Cycles 3.4 (bench/run_lights.py; results
# in bench/results/DEVICE/lights/): the studio and world scenes of
# bench/scenes/lights, the reference and the GPU pipeline swept, and what the
# lights cost per pass.
.PHONY: bench-lights
bench-lights: install-deps $(BUILD)/Makefile
	cmake --build $(BUILD) -j $(JOBS) --target photonbridge exr_probe
	$(BENCH_PYTHON) bench/run_lights.py --exe $(BUILD)/photonbridge --probe $(BUILD)/tests/exr_probe $(if $(DEVICE),--device $(DEVICE)) $(BENCH_ARGS)

bench-quick: bench-build
	$(BENCH_PYTHON) bench/run_bench.py --quick --exe $(BUILD)/photonbridge $(if $(DEVICE),--device $(DEVICE)) $(BENCH_ARGS)

# The four density estimators side by side on every sample
# (bench/results/DEVICE/estimators/).
.PHONY: bench-estimators
bench-estimators: bench-build
	$(BENCH_PYTHON) bench/run_bench.py --mode estimators --no-cycles --no-internals --exe $(BUILD)/photonbridge $(if $(DEVICE),--device $(DEVICE)) $(BENCH_ARGS)

# The peers (bench/run_peers.py; bench/results/lavapipe/peers/PEERS.md):
# LuxCore PhotonGI and BIDIRVMCPU, Mitsuba 3 and Cycles 4.5 (tools/ venvs of
# install-deps) against the Embree reference, PSNR and HDR-FLIP, one thread
# each. BENCH_ARGS: e.g. --scenes cornell_box --minutes 18.
.PHONY: bench-peers
bench-peers: bench-build
	$(BENCH_PYTHON) bench/run_peers.py --exe $(BUILD)/photonbridge $(if $(DEVICE),--device $(DEVICE)) $(BENCH_ARGS)

# Blender's Principled BSDF against Cycles on the studio scenes, and what the
# Blender materials and Multiscatter GGX cost (bench/principled_studio.py;
# results in bench/results/DEVICE/principled/).
.PHONY: bench-principled
bench-principled: install-deps $(BUILD)/Makefile
	cmake --build $(BUILD) -j $(JOBS) --target photonbridge exr_probe
	$(BENCH_PYTHON) bench/principled_studio.py --exe $(BUILD)/photonbridge --probe $(BUILD)/tests/exr_probe $(if $(DEVICE),--device $(DEVICE)) $(BENCH_ARGS)
# The Blender add-on's hand-off and first picture against Cycles
# (bench/blender_handoff.py; bench/results/lavapipe/blender/HANDOFF.md).
.PHONY: bench-blender
bench-blender: bench-build
	$(BENCH_PYTHON) bench/blender_handoff.py $(BUILD)/photonbridge
	$(BENCH_PYTHON) bench/blender_handoff.py $(BUILD)/photonbridge --bpy tools/bpy45/bin/python
