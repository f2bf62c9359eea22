#!/usr/bin/env bash
# pushpred reproduce: the paper's study end to end, on the simulated cases and the real ABS pushes.
set -u
bin=$1
data=$2
source "$(dirname "$0")/cli_support.sh"

expect_exit 0 "reproduce with the real data" -- "$bin" reproduce --data "$data" --out "$tmp/r"
# The same rule as predict on the same files: the 13 frozen-sensor pushes are listed skips, exit 0.
expect_in "$tmp/err" "SKIPPED $data/abs/motion_surface=abs_shape=rect1" "a frozen-sensor push is listed as skipped"
expect_not_in "$tmp/err" "FAILED" "no real push fails"
for section in "Table I" "Table II" "Figures 2 and 4" "Figure 5" "Figure 6" "Figure 7" "Figure 8" "Figure 9" \
  "The paper's claims" "every real ABS push" "force sensor frozen"; do
  expect_in "$tmp/r/report.md" "$section" "report.md has '$section'"
done
for f in summary.json cases/case1.h5 cases/case6.h5 fig5.gp fig5.dat fig2_4/observer.csv; do
  if [ -s "$tmp/r/$f" ]; then passed=$((passed + 1)); else failed=$((failed + 1)); echo "FAIL: $f missing"; fi
done
expect_in "$tmp/r/summary.json" '"aggregate_by_group"' "summary.json groups the cases and the real pushes"
expect_in "$tmp/r/summary.json" '"paper_cases_simulated": true' "summary.json says the cases are simulated"
expect_in "$tmp/out" "77 real pushes, 13 real pushes left out with reasons" "every real push is accounted for"
# The simulated cases read like real recordings.
expect_exit 0 "inspect the simulated cases" -- "$bin" inspect "$tmp/r/cases" --shape rect2
expect_in "$tmp/out" "6 files read, 0 failed" "the six cases pass inspect"

expect_exit 2 "--cases needs six files" -- "$bin" reproduce --out "$tmp/s" --cases a.h5 b.h5
expect_absent "$tmp/s" "output written on a bad argument"
expect_exit 2 "a missing data folder" -- "$bin" reproduce --data "$tmp/nowhere" --out "$tmp/s"
expect_in "$tmp/err" "data folder does not exist" "the missing folder is named"
expect_absent "$tmp/s" "output written for a missing data folder"
finish
