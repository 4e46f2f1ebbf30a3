# The two commands of the quick start, and the developer targets around them.
#   make render   set up, build (Release) and render the bundled example to out/
#   make test     set up, build and run the test suite
#   make install PREFIX=/opt/veach  headers, libveach and its image module, CMake package, veach.pc, `veach`, the add-on
#   make test-sanitize  the whole suite under ASan + UBSan (build-sanitize/, reduced sample counts)
#   make test-robustness  robustness tests + the attack suite's multi-GB originals (~3 GB disk)
#   make fuzz FUZZ_SECONDS=N  libFuzzer on the importer and on load + render (build-fuzz/, clang 14)
#   make gallery  render examples/gallery and write its contact sheet, docs/gallery.png
BUILD_DIR ?= build
JOBS ?= $(shell nproc)
CMAKE_FLAGS ?=

SANITIZE_DIR ?= build-sanitize
FUZZ_DIR ?= build-fuzz
FUZZ_SECONDS ?= 60

.PHONY: all deps configure build render test test-sanitize test-robustness fuzz bench gallery install clean

all: build

deps:
	@bash scripts/install-deps.sh

configure: deps
	@cmake -S . -B $(BUILD_DIR) -DCMAKE_BUILD_TYPE=Release $(CMAKE_FLAGS) >/dev/null

build: configure
	@cmake --build $(BUILD_DIR) -j $(JOBS)

render: build
	@mkdir -p out
	$(BUILD_DIR)/veach render examples/cornell/cornell.gltf -o out/cornell.exr -o out/cornell.png --width 512 --spp 64

test: build
	@cd $(BUILD_DIR) && ctest --output-on-failure -j $(JOBS)

install: build
	cmake --install $(BUILD_DIR) $(if $(PREFIX),--prefix $(PREFIX))

# Sanitizers make rays ~10x dearer: VEACH_TEST_SPP_DIVISOR divides the render tests' sample
# counts (their tolerances widen by its square root). Any report fails the test that caused it.
# LD_LIBRARY_PATH: ASan intercepts dlopen, so the image module (libveach_image_io.so) is looked
# up as if by libasan, without the test programs' RUNPATH that finds it in a plain build.
test-sanitize: deps
	@cmake -S . -B $(SANITIZE_DIR) -DCMAKE_BUILD_TYPE=RelWithDebInfo -DVEACH_SANITIZE=ON $(CMAKE_FLAGS) >/dev/null
	@cmake --build $(SANITIZE_DIR) -j $(JOBS)
	@cd $(SANITIZE_DIR) && VEACH_TEST_SPP_DIVISOR=8 LD_LIBRARY_PATH=$(CURDIR)/$(SANITIZE_DIR) \
	  ASAN_OPTIONS=detect_leaks=1:abort_on_error=1:detect_stack_use_after_return=0 \
	  LSAN_OPTIONS=suppressions=$(CURDIR)/tests/robustness/lsan.supp:print_suppressions=0 \
	  UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
	  ctest --output-on-failure -j $(JOBS)

# The robustness tests plus the attack suite's multi-gigabyte originals (about 3 GB of disk in the
# build folder, removed afterwards; a few minutes).
test-robustness: build
	@cd $(BUILD_DIR) && ctest --output-on-failure -j $(JOBS) -L robustness
	@/usr/bin/python3 tests/robustness/check_attack_suite.py --generate --full-size --veach $(BUILD_DIR)/veach \
	  --cases $(BUILD_DIR)/attack_cases_full; status=$$?; rm -rf $(BUILD_DIR)/attack_cases_full; exit $$status

# libFuzzer for FUZZ_SECONDS on each of FUZZ_TARGETS: importer (the glTF importer alone) and render
# (load through the C API, then a few samples of pt, bdpt or lt); new inputs go to
# $(FUZZ_DIR)/corpus-TARGET, findings to $(FUZZ_DIR)/findings-TARGET (turn each into a regression
# test in tests/robustness/data). Both start from fuzz/corpus. -timeout is the hang detector, not
# a speed target: a 4 KB Draco stream may declare up to the import's 512 MiB geometry base, and
# decoding that much legitimately takes 10-25 s in the instrumented build; 60 s still catches any
# loop that does not end.
FUZZ_TARGETS ?= importer render
fuzz:
	@bash scripts/install-deps.sh --fuzz
	@cmake -S . -B $(FUZZ_DIR) -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_C_COMPILER=clang-14 \
	  -DCMAKE_CXX_COMPILER=clang++-14 -DVEACH_FUZZ=ON -DVEACH_BUILD_TESTS=OFF >/dev/null
	@cmake --build $(FUZZ_DIR) -j $(JOBS) $(foreach t,$(FUZZ_TARGETS),--target veach_fuzz_$(t))
	@set -e; for t in $(FUZZ_TARGETS); do \
	  mkdir -p $(FUZZ_DIR)/corpus-$$t $(FUZZ_DIR)/findings-$$t; \
	  echo "== fuzz $$t for $(FUZZ_SECONDS) s"; \
	  ASAN_OPTIONS=detect_leaks=0 UBSAN_OPTIONS=halt_on_error=1 $(FUZZ_DIR)/fuzz/veach_fuzz_$$t \
	    $(FUZZ_DIR)/corpus-$$t fuzz/corpus -max_total_time=$(FUZZ_SECONDS) -timeout=60 -rss_limit_mb=2048 \
	    -max_len=65536 -artifact_prefix=$(FUZZ_DIR)/findings-$$t/ -print_final_stats=1; \
	done

# About ten minutes on two cores; GALLERY_SPP_SCALE=0.1 for a quick look (not for committing).
GALLERY_SPP_SCALE ?= 1
gallery: build
	@/usr/bin/python3 scripts/gallery.py --veach $(BUILD_DIR)/veach --spp-scale $(GALLERY_SPP_SCALE)

bench: build
	@bash scripts/install-deps.sh --bench
	@/usr/bin/python3 scripts/bench.py --build $(BUILD_DIR)

clean:
	rm -rf $(BUILD_DIR) out
