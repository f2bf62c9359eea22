#!/usr/bin/env bash
# pushpred inspect and the executable's common behaviour, run against the real data.
set -u
bin=$1
data=$2
source "$(dirname "$0")/cli_support.sh"

expect_exit 0 "--version" -- "$bin" --version
expect_in "$tmp/out" "pushpred 0." "--version prints the version"
expect_exit 0 "--help" -- "$bin" --help
expect_in "$tmp/out" "inspect" "--help lists the inspect subcommand"
expect_exit 2 "an unknown flag is refused by the parser" -- "$bin" inspect --frobnicate "$data/abs"
expect_in "$tmp/err" "frobnicate" "the unknown flag is named"

expect_exit 0 "inspect over all real data" -- "$bin" inspect "$data"
expect_in "$tmp/out" "91 files read, 0 failed" "no real file is lost"
expect_in "$tmp/out" "frozen_force_sensor" "frozen force sensors are flagged"
expect_in "$tmp/out" "rest force before the tip moves (p: a preload, pointing into the contact)" \
  "the rest forces are told apart into preloads and the sensor's zero"

expect_exit 0 "inspect --json" -- "$bin" inspect --json "$data/plywood"
expect_in "$tmp/out" '"failures": []' "JSON lists no failures"
expect_in "$tmp/out" '"surface": "plywood"' "JSON names the surface"
expect_in "$tmp/out" '"rest_preload"' "JSON says whether the rest force is a preload"

# A batch goes on past bad files and lists every failure with its reason.
printf 'not a recording' > "$tmp/junk.h5"
good=$(abs_push '')
expect_exit 1 "a batch with bad files" -- "$bin" inspect "$tmp/missing.h5" "$good" "$tmp/junk.h5"
expect_in "$tmp/out" "1 files read, 2 failed" "the good file is still inspected"
expect_in "$tmp/err" "FAILED $tmp/missing.h5: file does not exist" "the missing file is named"
expect_in "$tmp/err" "FAILED $tmp/junk.h5: neither an HDF5 nor a JSON recording" "the junk file is named"
expect_in "$tmp/err" "2 of 3 inputs failed" "the failures are counted"

cp "$good" "$tmp/push.h5"
expect_exit 2 "a file name without the shape (no input usable)" -- "$bin" inspect "$tmp/push.h5"
expect_in "$tmp/err" "give the shape with --shape" "the user is told to give --shape"
expect_exit 0 "the shape from a flag" -- "$bin" inspect --shape butter "$tmp/push.h5"
expect_exit 2 "an unknown shape from a flag" -- "$bin" inspect --shape teapot "$tmp/push.h5"
expect_in "$tmp/err" "unknown shape 'teapot'" "the unknown shape is named"
finish
