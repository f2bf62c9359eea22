#!/usr/bin/env bash
# The whole project built with AddressSanitizer and UndefinedBehaviorSanitizer (g++, as the main build), then the
# whole test suite run on it: any memory error, leak or undefined behaviour fails the test that hit it. CI runs it
# after the main suite (.ci/run). Usage: bash scripts/sanitize.sh [BUILD_DIR]   (default build-sanitize)
# Leaks inside third-party libraries are suppressed by scripts/lsan.supp, each with its reason.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build-sanitize}
# Through the environment, so that the projects the suite itself configures (tests/install's consumer) get them too.
export CXXFLAGS="-fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer"
export LDFLAGS="-fsanitize=address,undefined"
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=0:detect_stack_use_after_return=0"
export LSAN_OPTIONS="suppressions=$PWD/scripts/lsan.supp:print_suppressions=0"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
# Boost test cases labelled slow (studies over many simulated pushes, minutes each at -O1 with the sanitizers) are
# left out: the other cases run every path they take. Their ctest entries carry the label slow (tests/CMakeLists.txt).
export BOOST_TEST_RUN_FILTERS='!@slow'
launcher=()
if command -v ccache >/dev/null; then launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache); fi
start=$(date +%s)
# -O1 keeps the instrumented suite fast enough for CI; benchmarks are not part of the suite. The Python module is
# left out: under ASan the interpreter would need the runtime preloaded, and the C++ suite covers the same library.
# So is MPI (Open MPI's run-time is not run under the leak check; cli_mpi runs in the Release build): this build
# checks pushpred without it, where mpirun is refused and --shard / merge remain.
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_FLAGS_RELEASE="-O1 -DNDEBUG" \
  -DPUSHPRED_BUILD_BENCHMARKS=OFF -DPUSHPRED_BUILD_PYTHON=OFF -DPUSHPRED_WARNINGS_AS_ERRORS=OFF -DPUSHPRED_WITH_MPI=OFF "${launcher[@]}" >/dev/null
cmake --build "$build" -j2
built=$(date +%s)
status=0
# fuzz_short is left out: the fuzz targets are built with ASan and UBSan already (fuzz/CMakeLists.txt).
ctest --test-dir "$build" -j2 --output-on-failure -E fuzz_short -LE slow || status=$?
done_at=$(date +%s)
echo "sanitize: build $((built - start)) s, test suite $((done_at - built)) s"
exit $status
