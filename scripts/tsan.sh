#!/usr/bin/env bash
# The batch runner and the HDF5 reader's fork server under ThreadSanitizer (g++ -fsanitize=thread): test_runtime's
# `batch` suite (outcomes handed over in input order from two threads, an error while consuming) and
# test_isolated_server (servers on several threads, a crash or a hang in a child). Any data race fails the run.
# CI runs it after the other sanitizers (.ci/run). Usage: bash scripts/tsan.sh [BUILD_DIR]   (default build-tsan)
#
# Not run under it, and why (docs/robustness.md):
# - test_runtime's staged-output tests, which stop processes with signals and fork children that take them: under
#   ThreadSanitizer they did not finish within minutes, and `a_fork_waits_until_no_other_worker_is_inside_an_item`
#   draws a report of a signal-unsafe call (an exception allocated inside a signal handler's reach) still to be
#   traced; the AddressSanitizer build runs them.
# - `--jobs 2` end to end (cli_jobs) and the Python module under threads (an interpreter not built with the tool
#   reports races inside itself): the Release build runs them.
# - MPI (Open MPI's progress threads are not instrumented): cli_mpi runs in the Release build.
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
cmake --build "$build" -j2 --target test_runtime test_isolated_server
built=$(date +%s)
status=0
(cd "$build/tests/runtime" && timeout 600 ./test_runtime --run_test=batch --report_level=short) || status=$?
(cd "$build/tests/runtime" && timeout 600 ./test_isolated_server --report_level=short) || status=$?
done_at=$(date +%s)
echo "tsan: build $((built - start)) s, tests $((done_at - built)) s"
exit $status
