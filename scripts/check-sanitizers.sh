#!/usr/bin/env bash
# The whole test suite under AddressSanitizer + UndefinedBehaviorSanitizer (issue 16), in its own build
# folder (-DUASCMA_SANITIZE=ON, top CMakeLists.txt). Any memory error, leak or undefined behaviour fails
# the test that hit it. Usage: check-sanitizers.sh [BUILD_DIR [JOBS]]
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build-asan}
jobs=${2:-$(nproc)}
launcher=()
if command -v ccache >/dev/null; then launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache); fi

start=$(date +%s)
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release -DUASCMA_SANITIZE=ON -DUASCMA_BUILD_BENCHMARKS=OFF \
  "${launcher[@]}" >/dev/null
cmake --build "$build" -j "$jobs"
built=$(date +%s)

# halt_on_error / abort: a report fails the process (the CLI tests spawn the tool, which inherits these).
export ASAN_OPTIONS=detect_leaks=1:check_initialization_order=1:strict_init_order=1:detect_stack_use_after_return=1:abort_on_error=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
status=0
(cd "$build" && ctest --output-on-failure -j "$jobs" --timeout 3600) || status=$?
done_at=$(date +%s)
echo "check-sanitizers: build $((built - start)) s, tests $((done_at - built)) s, $(date -u +%Y-%m-%d), exit $status"
exit $status
