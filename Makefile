# fuzzycsg — the two commands of the README:
#   make demo   installs missing Debian packages, builds Release, runs the demo
#   make test   same set-up, then the whole test suite through ctest
# Other targets: build, asan (tests under AddressSanitizer + UBSan), format, format-check,
# fuzz (bounded libFuzzer run), bench, gallery (docs/gallery's pictures), clean.

JOBS ?= $(shell nproc)
PRESET ?= release
BUILD_DIR = build/$(PRESET)
WERROR ?= OFF
FUZZ_SECONDS ?= 60

.PHONY: all deps configure build demo test asan format format-check fuzz bench gallery clean

all: build

deps:
	@bash scripts/install-deps.sh

configure: deps
	@cmake --preset $(PRESET) -DFUZZYCSG_WERROR=$(WERROR) > /dev/null

build: configure
	@cmake --build $(BUILD_DIR) -j $(JOBS)

demo: build
	@$(BUILD_DIR)/apps/fuzzycsg/fuzzycsg demo

test: build
	@ctest --test-dir $(BUILD_DIR) --output-on-failure -j $(JOBS)

asan:
	@$(MAKE) --no-print-directory test PRESET=asan

format:
	@git ls-files '*.cpp' '*.hpp' | xargs clang-format -i

format-check:
	@git ls-files '*.cpp' '*.hpp' | xargs clang-format --dry-run --Werror

fuzz: deps
	@bash scripts/fuzz.sh $(FUZZ_SECONDS)

bench: deps
	@bash bench/run_eval_bench.sh

gallery:
	@bash scripts/make-gallery.sh

clean:
	@rm -rf build
