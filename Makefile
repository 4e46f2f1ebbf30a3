# The two commands of the quick start, and the developer targets around them.
#   make render   set up, build (Release) and render the bundled example to out/
#   make test     set up, build and run the test suite
BUILD_DIR ?= build
JOBS ?= $(shell nproc)
CMAKE_FLAGS ?=

.PHONY: all deps configure build render test bench clean

all: build

deps:
	@bash scripts/install-deps.sh

configure: deps
	@cmake -S . -B $(BUILD_DIR) -DCMAKE_BUILD_TYPE=Release $(CMAKE_FLAGS) >/dev/null

build: configure
	@cmake --build $(BUILD_DIR) -j $(JOBS)

render: build
	@mkdir -p out
	$(BUILD_DIR)/veach render examples/cornell/cornell.gltf -o out/cornell.exr -o out/cornell.png --width 512 --spp 256

test: build
	@cd $(BUILD_DIR) && ctest --output-on-failure -j $(JOBS)

bench: build
	@bash scripts/install-deps.sh --bench
	@/usr/bin/python3 scripts/bench.py --build $(BUILD_DIR)

clean:
	rm -rf $(BUILD_DIR) out
