#!/usr/bin/env bash
# The threaded parts under ThreadSanitizer (g++ -fsanitize=thread): the batch runner and the HDF5 reader's child
# processes (test_core, test_isolated_server, test_reading), and `--jobs 2` end to end (cli_jobs, which diagnoses,
# predicts and inspects real pushes on two threads and compares the outputs with one thread's). Any data race fails the test that hit it.
# CI runs it after the other sanitizers (.ci/run). Usage: bash scripts/tsan.sh [BUILD_DIR]   (default build-tsan)
#
# Not run under it: the Python module under threads (an interpreter not built with ThreadSanitizer reports races
# inside itself, and its GIL hand-offs are invisible to the tool; tests/python/test_gil.py runs the module's threads
# in the Release build), and MPI (Open MPI's progress threads are not instrumented; cli_mpi runs in the Release build).
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build-tsan}
export CXXFLAGS="-fsanitize=thread -fno-omit-frame-pointer"
export LDFLAGS="-fsanitize=thread"
# halt_on_error: the first race ends the test with a report. second_deadlock_stack: both stacks of a lock-order report.
export TSAN_OPTIONS="halt_on_error=1:second_deadlock_stack=1"
launcher=()
if command -v ccache >/dev/null; then launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache); fi
start=$(date +%s)
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_FLAGS_RELEASE="-O1 -DNDEBUG" \
  -DPUSHPRED_BUILD_BENCHMARKS=OFF -DPUSHPRED_BUILD_PYTHON=OFF -DPUSHPRED_BUILD_EXAMPLES=OFF \
  -DPUSHPRED_WARNINGS_AS_ERRORS=OFF -DPUSHPRED_WITH_MPI=OFF "${launcher[@]}" >/dev/null
cmake --build "$build" -j2 --target pushpred test_core test_isolated_server test_reading
built=$(date +%s)
status=0
ctest --test-dir "$build" --output-on-failure -R '^(test_core|test_isolated_server|test_reading|cli_jobs)$' || status=$?
done_at=$(date +%s)
echo "tsan: build $((built - start)) s, tests $((done_at - built)) s"
exit $status
