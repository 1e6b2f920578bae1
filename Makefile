# uascma — the two set-up commands are `make demo` and `make test` (README.md).
BUILD_DIR ?= build
JOBS ?= $(shell nproc)
CMAKE_FLAGS ?= -DCMAKE_BUILD_TYPE=Release

.PHONY: deps configure build demo test bench clean check-sanitizers fuzz
# `make check-sanitizers`: the whole suite under ASan + UBSan in its own build folder (issue 16).
SANITIZE_BUILD_DIR ?= build-asan
# `make fuzz FUZZ_SECONDS=N [FUZZ_PARALLEL=P]`: every parser's libFuzzer harness for N seconds, P at a time.
FUZZ_BUILD_DIR ?= build-fuzz
FUZZ_SECONDS ?= 60
FUZZ_PARALLEL ?= 1

deps:
	bash scripts/install-deps.sh

configure: deps
	cmake -S . -B $(BUILD_DIR) $(CMAKE_FLAGS)

build: configure
	cmake --build $(BUILD_DIR) -j $(JOBS)

demo: build
	bash scripts/demo.sh $(BUILD_DIR)

test: build
	cd $(BUILD_DIR) && ctest --output-on-failure -j $(JOBS) --timeout 900

bench: build
	bash scripts/bench.sh $(BUILD_DIR)

check-sanitizers: deps
	bash scripts/check-sanitizers.sh $(SANITIZE_BUILD_DIR) $(JOBS)

fuzz: deps
	bash scripts/fuzz.sh $(FUZZ_BUILD_DIR) $(FUZZ_SECONDS) $(JOBS) $(FUZZ_PARALLEL)

clean:
	rm -rf $(BUILD_DIR)
