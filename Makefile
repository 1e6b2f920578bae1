# uascma — the two set-up commands are `make demo` and `make test` (README.md).
BUILD_DIR ?= build
JOBS ?= $(shell nproc)
CMAKE_FLAGS ?= -DCMAKE_BUILD_TYPE=Release

# `make demo` builds only the library and the command-line tool (what the demo runs; its plots need only
# Debian's python3-matplotlib): no tests, benchmarks, Python module or MPI launcher (uascma-mpi), and installs only
# the `build` and `plots` packages (Open MPI, with its compilers and fabric libraries, is in the `test` group).
# `make test` (and build, bench) configures the same folder with everything on and builds the rest.
# The packages the compiles do not read (`plots`, `test-tools`) install in the background while they run
# (scripts/install-deps.sh --start/--wait); the build waits for them before anything runs.
# Ninja when it is there (scripts/install-deps.sh installs it): it starts any object whose inputs exist, where
# Make's generator waits for each library's dependencies to be built first, leaving a core idle at each library
# and at each precompiled header (docs/performance.md#set-up-time). A build folder keeps the generator it was
# configured with. Evaluated when the recipe runs, i.e. after its first line has installed Ninja.
GENERATOR = $$([ -f $(BUILD_DIR)/CMakeCache.txt ] || ! command -v ninja >/dev/null || echo "-G Ninja")
DEPS_WAIT_DIR = $(BUILD_DIR)/.deps-background
DEMO_OPTIONS = -DUASCMA_BUILD_TESTS=OFF -DUASCMA_BUILD_BENCHMARKS=OFF -DUASCMA_BUILD_PYTHON=OFF -DUASCMA_WITH_MPI=OFF
# The check that every header compiles alone (158 headers, ~9 CPU-minutes: a third of building the tests) is not part
# of `make test`; `make check-headers` runs it, and so does `make check-sanitizers` (docs/building.md).
FULL_OPTIONS = -DUASCMA_BUILD_TESTS=ON -DUASCMA_BUILD_BENCHMARKS=ON -DUASCMA_BUILD_PYTHON=ON -DUASCMA_WITH_MPI=ON \
	-DUASCMA_HEADER_CHECK=OFF

.PHONY: deps deps-demo configure build demo test bench clean check-headers check-sanitizers fuzz
# `make check-sanitizers`: the whole suite under ASan + UBSan in its own build folder.
SANITIZE_BUILD_DIR ?= build-asan
# `make fuzz FUZZ_SECONDS=N [FUZZ_PARALLEL=P]`: every parser's libFuzzer harness for N seconds, P at a time.
FUZZ_BUILD_DIR ?= build-fuzz
FUZZ_SECONDS ?= 60
FUZZ_PARALLEL ?= 1

deps:
	bash scripts/install-deps.sh build plots test test-tools

deps-demo:
	bash scripts/install-deps.sh build plots

configure:
	bash scripts/install-deps.sh build test
	bash scripts/install-deps.sh --start $(DEPS_WAIT_DIR) plots test-tools
	cmake $(GENERATOR) -S . -B $(BUILD_DIR) $(CMAKE_FLAGS) $(FULL_OPTIONS)

build: configure
	cmake --build $(BUILD_DIR) -j $(JOBS)
	bash scripts/install-deps.sh --wait $(DEPS_WAIT_DIR)

demo:
	bash scripts/install-deps.sh build
	bash scripts/install-deps.sh --start $(DEPS_WAIT_DIR) plots
	cmake $(GENERATOR) -S . -B $(BUILD_DIR) $(CMAKE_FLAGS) $(DEMO_OPTIONS)
	cmake --build $(BUILD_DIR) --target uascma_cli -j $(JOBS)
	bash scripts/install-deps.sh --wait $(DEPS_WAIT_DIR)
	bash scripts/demo.sh $(BUILD_DIR)

test: build
	cd $(BUILD_DIR) && ctest --output-on-failure -j $(JOBS) --timeout 900

bench: build
	cmake --build $(BUILD_DIR) --target benchmarks -j $(JOBS)
	bash scripts/bench.sh $(BUILD_DIR)

check-headers: deps
	cmake $(GENERATOR) -S . -B $(BUILD_DIR) $(CMAKE_FLAGS) $(FULL_OPTIONS) -DUASCMA_HEADER_CHECK=ON
	cmake --build $(BUILD_DIR) --target uascma_header_check -j $(JOBS)

check-sanitizers:
	bash scripts/install-deps.sh build plots test test-tools fuzz
	bash scripts/check-sanitizers.sh $(SANITIZE_BUILD_DIR) $(JOBS)

fuzz:
	bash scripts/install-deps.sh build test fuzz
	bash scripts/fuzz.sh $(FUZZ_BUILD_DIR) $(FUZZ_SECONDS) $(JOBS) $(FUZZ_PARALLEL)

clean:
	rm -rf $(BUILD_DIR)
