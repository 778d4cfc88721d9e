# photonbridge: the two commands of the README.
#   make demo   install what is missing, build, render samples/cornell_box
#   make test   install, build (normal + ASan/UBSan), run the whole suite
# Other targets: build, build-asan, install-deps, clean.

JOBS ?= $(shell nproc)
BUILD ?= build
ASAN_BUILD ?= build-asan
CMAKE_FLAGS ?=

.PHONY: all demo test build build-asan install-deps clean test-fast

all: build

install-deps:
	@bash scripts/install-deps.sh

# The generated Makefile (not CMakeCache.txt, which a failed configure also
# leaves) marks a configured tree.
$(BUILD)/Makefile:
	cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=RelWithDebInfo $(CMAKE_FLAGS)

$(ASAN_BUILD)/Makefile:
	cmake -S . -B $(ASAN_BUILD) -DCMAKE_BUILD_TYPE=Debug -DPB_SANITIZE=ON $(CMAKE_FLAGS)

build: install-deps $(BUILD)/Makefile
	cmake --build $(BUILD) -j $(JOBS)

build-asan: install-deps $(ASAN_BUILD)/Makefile
	cmake --build $(ASAN_BUILD) -j $(JOBS)

demo: build
	@bash scripts/demo.sh $(BUILD)/photonbridge

# The whole suite, in the normal build and again under ASan + UBSan.
test: build build-asan
	cd $(BUILD) && ctest --output-on-failure -j $(JOBS)
	cd $(ASAN_BUILD) && ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 \
	  UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
	  ctest --output-on-failure -j $(JOBS) -LE no-sanitize

# The normal build's suite only.
test-fast: build
	cd $(BUILD) && ctest --output-on-failure -j $(JOBS)

clean:
	rm -rf $(BUILD) $(ASAN_BUILD) out
