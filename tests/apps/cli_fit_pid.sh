#!/usr/bin/env bash
# pushpred fit-pid on real pushes: outputs, skipped frozen sensors, bad flags and bad files.
set -u
bin=$1
data=$2
source "$(dirname "$0")/cli_support.sh"

hex=$(ls "$data"/abs/motion_surface=abs_shape=hex_*.h5 | head -2)
frozen=$(abs_push 'shape=rect1_')

# shellcheck disable=SC2086
expect_exit 0 "a joint and per-push fit over two hex pushes" -- "$bin" fit-pid $hex --out "$tmp/pid" --per-push
expect_in "$tmp/out" "fitted PID gains over 2 push(es)" "the fitted pushes are counted"
expect_in "$tmp/pid/pid_fit.md" "| paper (trial and error) | 46.6 | 34.6 | 15.4 | 117.2 | 137.8 | 24.5 |" \
  "the report states the paper's gains"
expect_in "$tmp/pid/pid_fit.md" "joint fit over 2 push(es)" "the report states the joint gains"
expect_in "$tmp/pid/pid_fit.md" "per push: median" "the report summarises the per-push gains"
expect_in "$tmp/pid/pid_gains.json" '"joint"' "pid_gains.json holds the joint fit"
[ "$(ls "$tmp/pid/forces" | wc -l)" -eq 2 ] && passed=$((passed + 1)) || {
  failed=$((failed + 1)); echo "FAIL: one forces CSV per push"; }

# A frozen force sensor is skipped with its reason, not a failure; alone it leaves nothing to fit.
# shellcheck disable=SC2086
expect_exit 0 "a frozen sensor among good pushes is skipped" -- "$bin" fit-pid $hex "$frozen" --out "$tmp/pid2"
expect_in "$tmp/err" "SKIPPED $frozen: " "the skipped file is named"
expect_exit 2 "only a frozen sensor" -- "$bin" fit-pid "$frozen" --out "$tmp/pid3"
expect_in "$tmp/err" "nothing written" "the user is told nothing was written"
expect_absent "$tmp/pid3" "no output folder"

# Bad files in a batch are listed; the good ones are still fitted.
printf 'not a recording' > "$tmp/junk.h5"
# shellcheck disable=SC2086
expect_exit 1 "a batch with a bad file" -- "$bin" fit-pid $hex "$tmp/junk.h5" --out "$tmp/pid4"
expect_in "$tmp/err" "FAILED $tmp/junk.h5: neither an HDF5 nor a JSON recording" "the bad file is named"
expect_in "$tmp/pid4/pid_fit.md" "joint fit over 2 push(es)" "the good files are fitted"

# Bad options fail before any file is read and write nothing.
# shellcheck disable=SC2086
expect_exit 2 "a negative roughness weight" -- "$bin" fit-pid $hex --lambda -1 --out "$tmp/pid5"
expect_in "$tmp/err" "lambda" "the bad weight is named"
expect_absent "$tmp/pid5" "no output for a bad flag"
expect_exit 2 "an unknown flag" -- "$bin" fit-pid --gains 3 "$frozen" --out "$tmp/pid6"
expect_exit 2 "a missing file alone" -- "$bin" fit-pid "$tmp/missing.h5" --out "$tmp/pid7"
expect_in "$tmp/err" "FAILED $tmp/missing.h5: file does not exist" "the missing file is named"
finish
