# uascma — the two set-up commands are `make demo` and `make test` (README.md).
BUILD_DIR ?= build
JOBS ?= $(shell nproc)
CMAKE_FLAGS ?= -DCMAKE_BUILD_TYPE=Release

# `make demo` builds only the library and the command-line tool (what the demo runs; its plots need only
# Debian's python3-matplotlib): no tests, benchmarks, Python module or MPI launcher (uascma-mpi), and installs only
# the `build` packages (Open MPI, with its compilers and fabric libraries, is in the `test` group).
# `make test` (and build, bench) configures the same folder with everything on and builds the rest.
DEMO_OPTIONS = -DUASCMA_BUILD_TESTS=OFF -DUASCMA_BUILD_BENCHMARKS=OFF -DUASCMA_BUILD_PYTHON=OFF -DUASCMA_WITH_MPI=OFF
FULL_OPTIONS = -DUASCMA_BUILD_TESTS=ON -DUASCMA_BUILD_BENCHMARKS=ON -DUASCMA_BUILD_PYTHON=ON -DUASCMA_WITH_MPI=ON

.PHONY: deps deps-demo configure build demo test bench clean check-sanitizers fuzz
# `make check-sanitizers`: the whole suite under ASan + UBSan in its own build folder.
SANITIZE_BUILD_DIR ?= build-asan
# `make fuzz FUZZ_SECONDS=N [FUZZ_PARALLEL=P]`: every parser's libFuzzer harness for N seconds, P at a time.
FUZZ_BUILD_DIR ?= build-fuzz
FUZZ_SECONDS ?= 60
FUZZ_PARALLEL ?= 1

deps:
	bash scripts/install-deps.sh build test

deps-demo:
	bash scripts/install-deps.sh build

configure: deps
	cmake -S . -B $(BUILD_DIR) $(CMAKE_FLAGS) $(FULL_OPTIONS)

build: configure
	cmake --build $(BUILD_DIR) -j $(JOBS)

demo: deps-demo
	cmake -S . -B $(BUILD_DIR) $(CMAKE_FLAGS) $(DEMO_OPTIONS)
	cmake --build $(BUILD_DIR) --target uascma_cli -j $(JOBS)
	bash scripts/demo.sh $(BUILD_DIR)

test: build
	cd $(BUILD_DIR) && ctest --output-on-failure -j $(JOBS) --timeout 900

bench: build
	cmake --build $(BUILD_DIR) --target benchmarks -j $(JOBS)
	bash scripts/bench.sh $(BUILD_DIR)

check-sanitizers:
	bash scripts/install-deps.sh build test fuzz
	bash scripts/check-sanitizers.sh $(SANITIZE_BUILD_DIR) $(JOBS)

fuzz:
	bash scripts/install-deps.sh build test fuzz
	bash scripts/fuzz.sh $(FUZZ_BUILD_DIR) $(FUZZ_SECONDS) $(JOBS) $(FUZZ_PARALLEL)

clean:
	rm -rf $(BUILD_DIR)
