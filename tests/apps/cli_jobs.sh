#!/usr/bin/env bash
# --jobs: every subcommand that takes several files writes the same bytes with 2 jobs as with 1 (issue 12), a
# failing file included; the failures are listed in the same order.
set -u
bin=$1
data=$2
source "$(dirname "$0")/cli_support.sh"

files=()
for pattern in 'shape=hex_a=0_v=50' 'shape=ellip1_a=0_v=20' 'shape=rect1' 'shape=ellip3_a=0_v=10' 'shape=butter_a=0_v=50'; do
  files+=("$(ls "$data"/abs/*"$pattern"*.h5 | head -1)")
done
files+=("$tmp/missing.h5")  # a failure in the middle of the list's end

# same_run NAME SUBCOMMAND ARGS...: runs it with --jobs 1 and --jobs 2 into $tmp/NAME1 and $tmp/NAME2 (when it takes
# --out) and compares the output folders and stdout byte for byte, and the FAILED lines of stderr.
same_run() {
  local name=$1 sub=$2
  shift 2
  local out1=() out2=()
  if [ "$1" = "--out" ]; then out1=(--out "$tmp/${name}1"); out2=(--out "$tmp/${name}2"); shift; fi
  "$bin" "$sub" "$@" "${out1[@]}" --jobs 1 >"$tmp/$name.out1" 2>"$tmp/$name.err1"
  local code1=$?
  "$bin" "$sub" "$@" "${out2[@]}" --jobs 2 >"$tmp/$name.out2" 2>"$tmp/$name.err2"
  local code2=$?
  sed -i "s#$tmp/${name}[12]#OUT#g" "$tmp/$name.out1" "$tmp/$name.out2"
  if [ "$code1" -eq "$code2" ]; then passed=$((passed + 1)); else failed=$((failed + 1)); echo "FAIL: $name: exit $code1 with 1 job, $code2 with 2"; fi
  if cmp -s "$tmp/$name.out1" "$tmp/$name.out2"; then passed=$((passed + 1)); else
    failed=$((failed + 1)); echo "FAIL: $name: stdout differs"; diff "$tmp/$name.out1" "$tmp/$name.out2" | head -5
  fi
  if diff <(grep -E '^(FAILED|SKIPPED|LEFT OUT)' "$tmp/$name.err1") <(grep -E '^(FAILED|SKIPPED|LEFT OUT)' "$tmp/$name.err2") >/dev/null; then
    passed=$((passed + 1)); else failed=$((failed + 1)); echo "FAIL: $name: the failures differ"; fi
  if [ ${#out1[@]} -gt 0 ]; then
    if diff -r "$tmp/${name}1" "$tmp/${name}2" >/dev/null; then passed=$((passed + 1)); else
      failed=$((failed + 1)); echo "FAIL: $name: output folders differ"; diff -r "$tmp/${name}1" "$tmp/${name}2" | head -5
    fi
  fi
}

# The command line first, the subcommand as $1, then --out when it takes one.
same_run predict predict --out "${files[@]}"
expect_in "$tmp/predict1/summary.json" '"failures"' "the missing file is a failure"
expect_in "$tmp/predict.err2" "force sensor frozen" "the frozen sensor is listed with 2 jobs"
same_run inspect inspect "${files[@]}"
same_run inspect_json inspect "${files[@]}" --json
same_run fitpid fit-pid --out "${files[@]}" --max-iterations 3
same_run diagnose diagnose --out "${files[@]}" --per-object --no-plots --quick-base
for method in dob quasi_static; do
  expect_in "$tmp/predict2/summary.json" "\"$method\"" "2 jobs ran $method"
done

"$bin" predict "${files[0]}" --out "$tmp/z" --jobs 0 >"$tmp/out" 2>"$tmp/err"
if [ $? -ne 0 ] && [ ! -e "$tmp/z" ]; then passed=$((passed + 1)); else failed=$((failed + 1)); echo "FAIL: --jobs 0 was taken"; fi
finish
