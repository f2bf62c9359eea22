#!/usr/bin/env bash
# Builds the libFuzzer targets with clang-14 (ASan + UBSan) and runs each for SECONDS, seeded with the real
# recordings (copied into the build folder, never into the repository) and the tiny hand-written seeds in
# fuzz/seeds. Exits non-zero on any finding; the input that caused it is left in the build folder (crash-*,
# leak-*, timeout-*). The test suite runs it for 20 s per target (ctest -R fuzz_short); a longer run:
#   bash fuzz/run_fuzz.sh 1800 build-fuzz
# Usage: run_fuzz.sh SECONDS [BUILD_DIR] [DATA_DIR]
set -euo pipefail
seconds=${1:-20}
here=$(cd "$(dirname "$0")" && pwd)
build=${2:-$here/../build-fuzz}
data=${3:-${PUSHPRED_DATA:-$here/../../shared/data/mcube}}
compiler=${CXX_FUZZ:-clang++-14}
mkdir -p "$build"
build=$(cd "$build" && pwd)
launcher=()
if command -v ccache >/dev/null; then launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache); fi
if [ ! -f "$build/CMakeCache.txt" ]; then
  cmake -S "$here" -B "$build" -DCMAKE_C_COMPILER="${CC_FUZZ:-clang-14}" -DCMAKE_CXX_COMPILER="$compiler" \
    -DCMAKE_BUILD_TYPE=RelWithDebInfo "${launcher[@]}" >/dev/null
fi
cmake --build "$build" -j2 >/dev/null

corpus=$build/corpus
mkdir -p "$corpus/json" "$corpus/hdf5" "$corpus/filename" "$corpus/partial_output"
cp "$here"/seeds/json/* "$corpus/json/"
cp "$here"/seeds/partial_output/* "$corpus/partial_output/"
# A few real files of each kind as seeds; their names seed the name parser. `head` ends these pipelines early, so
# find may die of SIGPIPE: with pipefail that would end the script, hence `|| true` (the seeds are still copied).
find "$data" -name '*.json' | head -2 | while read -r f; do cp "$f" "$corpus/json/real-$(basename "$f" | md5sum | cut -c1-8).json"; done || true
find "$data" -name '*.h5' | sort | awk 'NR % 30 == 1' | while read -r f; do cp "$f" "$corpus/hdf5/real-$(basename "$f" | md5sum | cut -c1-8).h5"; done || true
find "$data" -name '*.h5' -o -name '*.json' | head -20 | while read -r f; do
  basename "$f" | tr -d '\n' > "$corpus/filename/$(basename "$f" | md5sum | cut -c1-8)"; done || true

# libhdf5 asks malloc for what a corrupt size field says (hundreds of GB): the allocator returns NULL as it does
# outside the fuzzer, and libhdf5 reports an error, which pushpred turns into an InputError. So a huge single
# request is not a finding (allocator_may_return_null, malloc_limit_mb); a process growing past 2 GB still is.
status=0
for target in fuzz_json_reader fuzz_hdf5_reader fuzz_filename fuzz_partial_output; do
  kind=${target#fuzz_}
  kind=${kind%_reader}
  [ "$kind" = hdf5 ] || [ "$kind" = json ] || [ "$kind" = partial_output ] || kind=filename
  echo "fuzz: $target for $seconds s"
  (cd "$build" && ASAN_OPTIONS=detect_leaks=1:allocator_may_return_null=1 LSAN_OPTIONS=suppressions=$here/../scripts/lsan.supp:print_suppressions=0 UBSAN_OPTIONS=print_stacktrace=1 \
     "./$target" "$corpus/$kind" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -malloc_limit_mb=1000000 -print_final_stats=1 \
     -close_fd_mask=1 >"$build/$target.log" 2>&1) || { status=1; echo "fuzz: $target FOUND A PROBLEM"; tail -40 "$build/$target.log"; }
  grep -E "^stat::number_of_executed_units|^stat::new_units_added" "$build/$target.log" | tr '\n' ' '
  echo
done
exit $status
