#!/usr/bin/env bash
# pushpred predict and compare: outputs, failures listed, nothing written on a bad argument.
set -u
bin=$1
data=$2
source "$(dirname "$0")/cli_support.sh"

hex=$(abs_push 'shape=hex_a=0_v=50')
ellip=$(abs_push 'shape=ellip1_a=0_v=20')
frozen=$(abs_push 'shape=rect1')

expect_exit 0 "predict on two pushes" -- "$bin" predict "$hex" "$ellip" --out "$tmp/p"
expect_in "$tmp/out" "predicted 2 pushes (4 intervals over the whole span)" "the span used is said"
for key in x_mm_mean x_mm_std y_mm_mean y_mm_std theta_deg_mean theta_deg_std final_pos_mm final_theta_deg; do
  expect_in "$tmp/p/summary.json" "\"$key\"" "summary.json has $key"
done
for method in dob dob_velinit simple hold const_velocity quasi_static; do
  expect_in "$tmp/p/summary.json" "\"$method\"" "summary.json has method $method"
done
expect_in "$tmp/p/summary.json" '"pusher_friction"' "summary.json has the quasi-static parameters"
expect_in "$tmp/p/tables.md" "| hex | 1 | 3 |" "tables.md has the per-object table"
expect_in "$tmp/p/tables.md" "v =  50 mm/s" "tables.md has the per-speed table"
expect_in "$tmp/p/summary.json" '"aggregate"' "summary.json has the aggregate"
if ls "$tmp"/p/predictions/*.csv >/dev/null 2>&1; then passed=$((passed + 1)); else failed=$((failed + 1)); echo "FAIL: no per-push CSV"; fi

# A frozen force sensor is a listed skip (the push is valid; the method needs its force), not a failure: exit 0, as
# reproduce and fit-pid on the same files (docs/exit-codes.md).
expect_exit 0 "a frozen force sensor is a listed skip, the rest goes on" -- \
  "$bin" predict "$frozen" "$hex" --out "$tmp/q" --span contact
expect_in "$tmp/err" "SKIPPED $frozen: force sensor frozen" "the skip and its reason are given"
expect_in "$tmp/err" "1 of 2 inputs skipped" "the skips are counted"
expect_in "$tmp/q/summary.json" '"skipped": true' "the skip is in summary.json's failures, marked skipped"
expect_in "$tmp/out" "predicted 1 pushes (4 intervals over the contact span)" "the good push is predicted"
expect_exit 2 "only a frozen force sensor: nothing to predict" -- "$bin" predict "$frozen" --out "$tmp/q0"
expect_absent "$tmp/q0" "nothing written when only a skipped push is given"
expect_exit 1 "a skip and a failure: the failure sets the exit code" -- \
  "$bin" predict "$frozen" "$hex" "$tmp/missing.h5" --out "$tmp/q1"
expect_in "$tmp/err" "FAILED $tmp/missing.h5" "the failure is listed"

expect_exit 0 "methods chosen by name" -- "$bin" predict "$hex" --out "$tmp/m" --methods quasi_static,hold
expect_in "$tmp/out" "quasi_static" "the chosen method is printed"
expect_not_in "$tmp/m/summary.json" '"dob_velinit"' "a method not chosen ran"
expect_exit 2 "an unknown method" -- "$bin" predict "$hex" --out "$tmp/r" --methods hold,magic
expect_in "$tmp/err" "unknown prediction method 'magic'" "the unknown method is named"
expect_absent "$tmp/r" "output folder written on a bad method"

expect_exit 2 "an unknown estimator" -- "$bin" predict "$hex" --out "$tmp/r" --estimator magic
expect_in "$tmp/err" "magic" "the unknown estimator is named"
expect_absent "$tmp/r" "output folder written on a bad argument"
expect_exit 2 "a bad span" -- "$bin" predict "$hex" --out "$tmp/r" --span halfway
expect_exit 2 "a non-numeric rate" -- "$bin" predict "$hex" --out "$tmp/r" --plan-rate fast

# A push listed twice (and once more inside a listed folder) is studied once; two different files with the same
# name in two folders (copies here) each get their own predictions file, the same whatever --jobs.
mkdir -p "$tmp/twice/a" "$tmp/twice/b"
cp "$hex" "$tmp/twice/a/" && cp "$hex" "$tmp/twice/b/"
expect_exit 0 "the same push twice and a folder holding it" -- \
  "$bin" predict "$tmp/twice/a/$(basename "$hex")" "$tmp/twice/a/$(basename "$hex")" "$tmp/twice/a" --out "$tmp/t1"
expect_in "$tmp/out" "predicted 1 pushes" "a push reached three times is studied once"
expect_in "$tmp/err" "note: 2 inputs reach a push already given" "the user is told that two repeats were dropped"
for jobs in 1 2; do
  expect_exit 0 "two files of the same name, --jobs $jobs" -- "$bin" predict "$tmp/twice" --out "$tmp/t2-$jobs" --jobs "$jobs"
  expect_in "$tmp/out" "predicted 2 pushes" "both same-named files are studied (--jobs $jobs)"
  expect_not_in "$tmp/err" "already given" "different files of the same name are not called repeats (--jobs $jobs)"
done
stem=$(basename "$hex" .h5)
check "each same-named push has its own predictions file" \
  [ -f "$tmp/t2-1/predictions/$stem.csv" -a -f "$tmp/t2-1/predictions/$stem-2.csv" ]
expect_same_tree "$tmp/t2-1" "$tmp/t2-2" "--jobs 1 and 2 write the same files for same-named pushes"
# Names are given among the pushes studied: a failed input of the same name, listed first, takes none.
mkdir -p "$tmp/twice/bad" && echo garbage > "$tmp/twice/bad/$stem.h5"
expect_exit 1 "a failed same-named input before a good one" -- \
  "$bin" predict "$tmp/twice/bad/$stem.h5" "$tmp/twice/a/$stem.h5" --out "$tmp/t3"
check "the studied push keeps its name" [ -f "$tmp/t3/predictions/$stem.csv" ]
check "nothing else is in predictions/" [ "$(ls "$tmp/t3/predictions" | wc -l)" -eq 1 ]
expect_absent "$tmp/t3/by-input" "the waiting folder is gone"
# Two shards merged name the same-named pushes as one run does.
for i in 1 2; do
  expect_exit 0 "shard $i of same-named pushes" -- "$bin" predict "$tmp/twice/a" "$tmp/twice/b" --out "$tmp/s$i" --shard "$i/2"
done
expect_exit 0 "merge of the same-named pushes' shards" -- "$bin" merge --out "$tmp/t4" "$tmp/s1" "$tmp/s2"
expect_exit 0 "one run over the same-named pushes" -- "$bin" predict "$tmp/twice/a" "$tmp/twice/b" --out "$tmp/t5"
expect_same_tree "$tmp/t5" "$tmp/t4" "merged shards and one run name same-named pushes alike"

expect_exit 0 "compare RLS with batch fits" -- "$bin" compare "$hex" "$ellip" --out "$tmp/c" --estimators rls,batch,batch_huber
expect_in "$tmp/c/compare.md" "| rls |" "compare.md has the RLS row"
expect_in "$tmp/c/compare.md" "| batch_huber |" "compare.md has the Huber row"
finish
