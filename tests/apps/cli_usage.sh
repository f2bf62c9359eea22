#!/usr/bin/env bash
# How the program answers a user's slips (docs/exit-codes.md): a mistyped command names the nearest one, --help shows
# every option's default, no subcommand lists an option it always refuses, simulate without --out writes nothing.
set -u
bin=$1
source "$(dirname "$0")/cli_support.sh"

expect_exit 2 "a mistyped command" -- "$bin" predcit x.h5 --out "$tmp/p"
expect_in "$tmp/err" "unknown command 'predcit'; did you mean 'predict'?" "the nearest command is named"
expect_absent "$tmp/p" "nothing written for a mistyped command"
expect_exit 2 "a word far from every command" -- "$bin" xyzzy
expect_in "$tmp/err" "unknown command 'xyzzy'; the commands are: " "the commands are listed"
expect_in "$tmp/err" "validate-diagnosis" "every command is among them"
expect_exit 2 "a mistyped command with a dash" -- "$bin" fit_pid x.h5
expect_in "$tmp/err" "did you mean 'fit-pid'?" "fit_pid is taken for fit-pid"
expect_exit 0 "a real command still runs" -- "$bin" --version

# Defaults in --help, from the values the program uses.
expect_exit 0 "predict --help" -- "$bin" predict --help
expect_in "$tmp/out" "--intervals INT:INT in [2 - 100]=4" "the default schedule is shown"
expect_in "$tmp/out" "--rate FLOAT:POSITIVE=250" "the default rate is shown"
expect_in "$tmp/out" "--estimator TEXT=rls" "the default estimator is shown"
expect_exit 0 "fit-pid --help" -- "$bin" fit-pid --help
expect_in "$tmp/out" "--lambda FLOAT:POSITIVE=1" "fit-pid's default lambda is shown"
expect_exit 0 "observe --help" -- "$bin" observe --help
expect_in "$tmp/out" "--wn FLOAT:POSITIVE=300" "the observer's default frequency is shown"

# An option listed in a subcommand's --help is one it can take: --shard only where the work can be split.
for sub in inspect compare fit-pid observe plot bench reproduce simulate; do
  "$bin" "$sub" --help >"$tmp/help" 2>&1
  expect_not_in "$tmp/help" "--shard" "$sub does not list --shard"
done
for sub in predict validate-diagnosis diagnose; do
  "$bin" "$sub" --help >"$tmp/help" 2>&1
  expect_in "$tmp/help" "--shard" "$sub lists --shard"
done

# simulate without --out says so and writes nothing (it never picks a file name of its own).
mkdir -p "$tmp/here"
(cd "$tmp/here" && "$bin" simulate >"$tmp/out" 2>"$tmp/err")
check "simulate with no arguments exits 2" [ $? -eq 2 ]
expect_in "$tmp/err" "--out FILE.h5 (or a folder) is required" "simulate says --out is needed"
check "simulate with no arguments wrote nothing" [ -z "$(ls -A "$tmp/here")" ]
expect_exit 0 "simulate --case 1 --out FILE" -- "$bin" simulate --case 1 --out "$tmp/case1.h5"
expect_in "$tmp/out" "wrote $tmp/case1.h5" "simulate says what it wrote"

finish
