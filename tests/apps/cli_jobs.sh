#!/usr/bin/env bash
# --jobs: every subcommand that takes several files writes the same bytes with 2 jobs as with 1, a
# failing file included; the failures are listed in the same order.
set -u
bin=$1
data=$2
source "$(dirname "$0")/cli_support.sh"

batch_files

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
  check "$name: exit $code1 with 1 job, $code2 with 2" [ "$code1" -eq "$code2" ]
  if cmp -s "$tmp/$name.out1" "$tmp/$name.out2"; then passed=$((passed + 1)); else
    failed=$((failed + 1)); echo "FAIL: $name: stdout differs"; diff "$tmp/$name.out1" "$tmp/$name.out2" | head -5
  fi
  check "$name: the failures differ" \
    diff <(grep -E '^(FAILED|SKIPPED|LEFT OUT)' "$tmp/$name.err1") <(grep -E '^(FAILED|SKIPPED|LEFT OUT)' "$tmp/$name.err2")
  if [ ${#out1[@]} -gt 0 ]; then
    expect_same_tree "$tmp/${name}1" "$tmp/${name}2" "$name: output folders differ"
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
check "--jobs 0 was taken" [ $? -ne 0 ]
expect_absent "$tmp/z" "--jobs 0 wrote an output"
finish
