#!/usr/bin/env bash
# Issue 13: every class of bad input gives a clear per-file error naming the file, the batch goes on, the good
# files' results are those of a run without the bad ones, no command hangs, and nothing is left behind (no
# output on failure, no staging folder after a signal, no stale file in a re-used output folder).
set -u
bin=$1
data=$2
make_bad=$3
source "$(dirname "$0")/cli_support.sh"

good1=$(abs_push 'shape=hex_a=0_v=50')
good2=$(abs_push 'shape=ellip1_a=0_v=20')
name=$(basename "$good1")
bad="$tmp/bad"
"$make_bad" "$good1" "$bad" >/dev/null || { echo "FAIL: make_bad_inputs"; exit 1; }
stem=${name%.h5}

# No command may hang on a bad file: each run gets 30 s (a good push takes well under 5 s).
limit() { timeout 30 "$@"; }

# expect_plain FILE: no raw bytes (only printable ASCII, tabs and newlines) in FILE.
expect_plain() {
  if LC_ALL=C grep -q '[^[:print:][:space:]]' "$1"; then failed=$((failed + 1)); echo "FAIL: raw bytes in $(basename "$1")"
    LC_ALL=C grep -n '[^[:print:][:space:]]' "$1" | head -3 | cat -v; else passed=$((passed + 1)); fi
}
# expect_no_staging FOLDER: no hidden staging or replaced folder left in FOLDER.
expect_no_staging() {
  if ls -a "$1" | grep -q '\.staging-\|\.replaced-'; then failed=$((failed + 1)); echo "FAIL: $2: staging left in $1"
    ls -a "$1" | grep '\.staging-\|\.replaced-' | head -3; else passed=$((passed + 1)); fi
}

# Each class alone: inspect and predict name the file and the problem, exit 2 (nothing usable) within the time
# limit, and predict writes nothing.
check_class() {  # check_class CLASS EXT EXPECTED_TEXT
  local f="$bad/$1/$stem$2"
  expect_exit 2 "inspect on $1" -- limit "$bin" inspect "$f"
  expect_in "$tmp/err" "FAILED $f: $3" "$1: the file and the reason are named"
  expect_plain "$tmp/err"
  expect_exit 2 "predict on $1" -- limit "$bin" predict "$f" --out "$tmp/class_out"
  expect_in "$tmp/err" "FAILED $f: $3" "$1: predict names the file and the reason"
  expect_absent "$tmp/class_out" "$1: predict writes nothing"
}
check_class garbage .json "malformed JSON: parse error"
check_class overflow .json "malformed JSON: number overflow parsing '1e400'"
check_class nan_literal .json \
  "malformed JSON: parse error at line 1, column 23: syntax error while parsing value - invalid literal; last read: '1.5e9, N' (NaN and Infinity are not JSON numbers"
check_class array .json "JSON recording must be an object of three arrays (tip_pose, object_pose, ft_wrench), not an array"
check_class milliseconds .h5 "stream 'tip_pose' has time stamps near 1.46e+12, which are not Unix seconds (milliseconds?)"
check_class relative_milliseconds .h5 "stream 'tip_pose' runs at 0.227 Hz (median step 4.4 s), outside 25 to 2.5e+03 Hz"
check_class late_stamp .h5 "stream 'tip_pose' has a gap of 1e+05 s between rows 370 and 371"
check_class declared_rows .h5 "array 'tip_pose' declares 100000000 rows"
check_class integer_pose .h5 "array 'object_pose' holds 64-bit integers; the format stores 64-bit floats"
check_class huge_force .h5 "stream 'ft_wrench' has fx 1e+300 N at row 0, beyond the plausible 1e+03 N"
check_class far_away .h5 "stream 'object_pose' has x 1e+03 m at row"
check_class object_spike .h5 "object_pose moves at"
check_class object_step .h5 "object_pose moves at"
check_class yaw_turns .h5 "object_pose turns at"
check_class object_at_tip .h5 "the rod's surface lies 57.1 mm inside hex's outline"
check_class float32_unix .h5 "array 'tip_pose' stores its time stamps as 32-bit floats"
check_class nan_force .h5 "array 'ft_wrench' holds NaN at row 7, column 2"
check_class inf_pose .h5 "array 'object_pose' holds Inf at row 5, column 1"
check_class empty_stream .h5 "array 'tip_pose' is empty"
check_class single_row .h5 "array 'object_pose' has one sample; need at least two"
check_class missing_array .h5 "array 'ft_wrench' is missing"
check_class shuffled .h5 "array 'ft_wrench': time goes backwards by"
check_class truncated .h5 "not a complete HDF5 file: it holds"
expect_in "$tmp/err" "its header declares (cut short, as by an interrupted copy)" "truncated: the bytes declared are said"
check_class signature_only .h5 "not a complete HDF5 file: it holds 8 bytes and ends inside its header (the superblock at byte 0)"
check_class cut_in_header .h5 "not a complete HDF5 file: it holds 40 bytes, fewer than the 96 of its header (superblock)"

# Files other tools write that hold a usable push: HDF5 behind a user block, and 32-bit floats with time stamps from
# the push's start (converted, and said so).
expect_exit 0 "inspect an HDF5 file with a user block" -- limit "$bin" inspect "$bad/user_block/$stem.h5"
expect_exit 0 "inspect 32-bit float arrays" -- limit "$bin" inspect --json "$bad/float32/$stem.h5"
expect_in "$tmp/out" "tip_pose: stored as 32-bit floats: converted to 64-bit" "inspect says the arrays were converted"
expect_exit 0 "predict on both" -- limit "$bin" predict "$bad/user_block/$stem.h5" "$bad/float32/$stem.h5" \
  --out "$tmp/converted" --methods dob,hold
expect_in "$tmp/out" "predicted 2 pushes" "both are predicted"

# Good data behind a byte-order mark, and the same data as JSON and HDF5 under the real name, are read.
for f in "$bad/bom_good/$stem.json" "$bad/good/$stem.json" "$bad/good/$stem.h5"; do
  expect_exit 0 "inspect $(basename "$(dirname "$f")")/$(basename "$f")" -- limit "$bin" inspect "$f"
done

# Things that are not files.
mkdir -p "$tmp/odd/empty" "$tmp/odd/named/$name" "$tmp/odd/loopdir"
mkfifo "$tmp/odd/fifo.h5"
ln -s "$tmp/odd/loop.h5" "$tmp/odd/loop.h5"
ln -s "$tmp/odd/loopdir/x.h5" "$tmp/odd/loopdir/x.h5"
expect_exit 2 "a FIFO" -- limit "$bin" inspect "$tmp/odd/fifo.h5"
expect_in "$tmp/err" "FAILED $tmp/odd/fifo.h5: is a FIFO; only regular files are read" "the FIFO is refused by name"
expect_exit 2 "a symbolic-link loop" -- limit "$bin" inspect "$tmp/odd/loop.h5"
expect_in "$tmp/err" "FAILED $tmp/odd/loop.h5: cannot be read: Too many levels of symbolic links" "the loop is named"
expect_exit 2 "an empty folder" -- limit "$bin" inspect "$tmp/odd/empty"
expect_in "$tmp/err" "FAILED $tmp/odd/empty: is a folder holding no recordings (*.h5, *.json)" "the empty folder is named"
expect_exit 2 "a folder named like a recording" -- limit "$bin" inspect "$tmp/odd/named/$name"
expect_in "$tmp/err" "is a folder holding no recordings" "the folder is named"
expect_exit 2 "predict on an empty folder" -- limit "$bin" predict "$tmp/odd/empty" --out "$tmp/empty_out"
expect_absent "$tmp/empty_out" "nothing written when no input is usable"
expect_no_staging "$tmp" "predict on an empty folder"

# A batch of good and bad files: exit 1, every failure listed, the good results identical to a run without them.
expect_exit 0 "predict on the good files alone" -- limit "$bin" predict "$good1" "$good2" --out "$tmp/alone"
expect_exit 1 "predict on good and bad files" -- limit "$bin" predict "$bad/garbage/$stem.json" "$good1" \
  "$tmp/odd/loop.h5" "$tmp/odd/fifo.h5" "$bad/late_stamp/$stem.h5" "$bad/milliseconds/$stem.h5" \
  "$bad/declared_rows/$stem.h5" "$bad/integer_pose/$stem.h5" "$bad/huge_force/$stem.h5" "$bad/overflow/$stem.json" \
  "$tmp/odd/empty" "$tmp/odd/loopdir" "$good2" --out "$tmp/mixed"
expect_in "$tmp/err" "11 of 13 inputs failed" "every failure is counted"
expect_plain "$tmp/err"
for f in "$bad/garbage/$stem.json" "$tmp/odd/loop.h5" "$tmp/odd/fifo.h5" "$tmp/odd/loopdir/x.h5" "$tmp/odd/empty"; do
  expect_in "$tmp/err" "FAILED $f: " "the failure of $f is listed"
done
if jq -e '.failures | length == 11' "$tmp/mixed/summary.json" >/dev/null; then passed=$((passed + 1)); else
  failed=$((failed + 1)); echo "FAIL: summary.json does not list the 11 failures as valid JSON"; fi
if diff <(jq 'del(.failures)' "$tmp/alone/summary.json") <(jq 'del(.failures)' "$tmp/mixed/summary.json") >/dev/null &&
  diff -r "$tmp/alone/predictions" "$tmp/mixed/predictions" >/dev/null; then passed=$((passed + 1)); else
  failed=$((failed + 1)); echo "FAIL: the good files' results differ from a run of the good files alone"; fi

# A file name that is not UTF-8 still gives valid JSON.
odd_folder=$(printf '%s/name\377' "$tmp")
mkdir -p "$odd_folder" && cp "$good1" "$odd_folder/"
expect_exit 0 "predict on a file below a non-UTF-8 folder name" -- limit "$bin" predict "$odd_folder" --out "$tmp/utf"
if jq -e '.' "$tmp/utf/summary.json" >/dev/null; then passed=$((passed + 1)); else failed=$((failed + 1)); echo "FAIL: invalid JSON"; fi
expect_exit 0 "inspect --json on it" -- limit "$bin" inspect --json "$odd_folder"
if jq -e '.files | length == 1' "$tmp/out" >/dev/null; then passed=$((passed + 1)); else failed=$((failed + 1)); echo "FAIL: inspect JSON"; fi

# observe (one file): exit 2 with the file named, nothing written, in time.
for class in garbage late_stamp relative_milliseconds huge_force; do
  f=$(ls "$bad/$class/$stem".*)
  expect_exit 2 "observe on $class" -- limit "$bin" observe "$f" --out "$tmp/obs_$class" --no-plots
  expect_in "$tmp/err" "pushpred: error: $f: " "observe names the $class file"
  expect_absent "$tmp/obs_$class" "observe writes nothing on $class"
done
expect_no_staging "$tmp" "observe on bad files"

# Output folders: a re-used one is replaced as a whole; one pushpred did not write is refused and left alone.
expect_exit 0 "predict again into the same folder, on one push" -- limit "$bin" predict "$good1" --out "$tmp/alone"
count=$(ls "$tmp/alone/predictions" | wc -l)
if [ "$count" -eq 1 ]; then passed=$((passed + 1)); else failed=$((failed + 1)); echo "FAIL: $count per-push CSVs, not 1"; fi
mkdir -p "$tmp/mine" && echo keep > "$tmp/mine/notes.txt"
expect_exit 2 "an output folder pushpred did not write" -- limit "$bin" predict "$good1" --out "$tmp/mine"
expect_in "$tmp/err" "was not written by pushpred" "the user is told why"
expect_in "$tmp/mine/notes.txt" "keep" "the user's file is untouched"
echo x > "$tmp/afile"
expect_exit 2 "an output path that is a file" -- limit "$bin" predict "$good1" --out "$tmp/afile"
expect_in "$tmp/err" "exists and is not a folder" "the output file is named"

# A run stopped by SIGTERM or SIGINT removes its staging folder and writes nothing. timeout signals the process and
# then its whole group (the HDF5 reader's child too), so each run gets the signal twice, microseconds apart; runs
# stopped at 20 moments from 0.45 to 1.4 s (reading, predicting, writing) must all leave nothing.
mkdir -p "$tmp/sig"
# Enough work to be still running when stopped: one pass over abs/ takes about a second. A file given
# twice is studied once, and so is a file reached through hard links, so the 20 passes are over 20 copies.
mkdir -p "$tmp/slow" && cp -r "$data/abs" "$tmp/slow/1"
slow=("$tmp/slow/1")
for k in $(seq 2 20); do cp -r "$tmp/slow/1" "$tmp/slow/$k" && slow+=("$tmp/slow/$k"); done
stopped_ok=0
for i in $(seq 1 20); do
  if [ $((i % 2)) -eq 0 ]; then signal=TERM; else signal=INT; fi
  delay=$(awk -v i="$i" 'BEGIN { printf "%.2f", 0.4 + 0.05 * i }')
  # timeout runs pushpred in the foreground (a background job of a script would ignore SIGINT) and signals it.
  timeout -s "$signal" "$delay" "$bin" predict "${slow[@]}" --out "$tmp/sig/run" >/dev/null 2>&1
  code=$?
  if [ "$code" -ne 124 ]; then echo "FAIL: SIG$signal after $delay s: exit $code, expected 124"
  elif [ -e "$tmp/sig/run" ]; then echo "FAIL: SIG$signal after $delay s: output written"
  elif ls -a "$tmp/sig" | grep -q '\.staging-\|\.replaced-'; then
    echo "FAIL: SIG$signal after $delay s: staging left: $(ls -a "$tmp/sig" | grep staging | head -1)"
  else stopped_ok=$((stopped_ok + 1)); fi
  rm -rf "$tmp/sig"/.run.* "$tmp/sig/run"  # each run is judged alone
done
if [ "$stopped_ok" -eq 20 ]; then passed=$((passed + 1)); else failed=$((failed + 1))
  echo "FAIL: $((20 - stopped_ok)) of 20 stopped runs left something behind or ended otherwise"; fi
sleep 0 &
dead=$!
wait "$dead"
mkdir -p "$tmp/sig/.run.staging-$dead-1/predictions" && touch "$tmp/sig/.run.staging-$dead-1/.pushpred-output"
expect_exit 0 "a run after a killed one" -- limit "$bin" predict "$good1" --out "$tmp/sig/run"
expect_no_staging "$tmp/sig" "the stale staging folder of a dead run"

# A bad flag value is a bad argument: exit 2, a message naming the flag and the value, nothing written. nan and inf
# included (CLI11's own positive-number check let nan through: --mu nan meant "from the surface").
# --rate and --plan-rate 1e9 asked for billions of samples (std::bad_alloc, or the process killed for its memory).
for flag in "--mu nan" "--mu inf" "--mu -1" "--mu 1e300" "--plan-rate nan" "--plan-rate 0" "--rate inf" "--jobs 0" \
  "--rate 1e9" "--plan-rate 1e9"; do
  set -- $flag
  expect_exit 2 "predict $flag" -- limit "$bin" predict "$good1" --out "$tmp/flag" "$1" "$2"
  expect_in "$tmp/err" "$1: must be a" "predict $flag names the flag"
  expect_in "$tmp/err" "got '$2'" "predict $flag names the value"
  expect_absent "$tmp/flag" "predict $flag wrote an output"
done
# observe's and fit-pid's numbers the same way: a span beyond a push's 600 s, a Q-filter faster than the Nyquist
# frequency of a 2500 Hz stream or damped beyond 10 (1e300 gave "linear system: A or B holds NaN or infinity").
while read -r command flag value expected; do
  expect_exit 2 "$command $flag $value" -- limit "$bin" "$command" "$good1" --out "$tmp/flag" "$flag" "$value" </dev/null
  expect_in "$tmp/err" "$flag: must be $expected, got '$value'" "$command $flag $value names the flag and the bound"
  expect_absent "$tmp/flag" "$command $flag $value wrote an output"
done <<'FLAGS'
observe --start -1 a finite number in [0, 600]
observe --start nan a finite number in [0, 600]
observe --end 1e300 a finite number in (0, 600] or -1 (the push's end)
observe --wn 1e300 a positive finite number up to 7854
observe --zeta 1e300 a positive finite number up to 10
observe --zeta inf a positive finite number up to 10
fit-pid --lambda nan a positive finite number
fit-pid --lambda -1 a positive finite number
FLAGS
expect_exit 2 "an unknown flag" -- limit "$bin" predict "$good1" --out "$tmp/flag" --no-such-flag
expect_in "$tmp/err" "--no-such-flag" "the unknown flag is named"
expect_absent "$tmp/flag" "an unknown flag wrote an output"
expect_exit 2 "a subcommand that does not exist" -- limit "$bin" predcit "$good1"
expect_exit 0 "--help" -- limit "$bin" predict --help
expect_in "$tmp/out" "--mu FLOAT:NONNEGATIVE" "--help shows the check's name"

expect_exit 2 "a plan rate above the grid's" -- limit "$bin" predict "$good1" --out "$tmp/flag" --rate 100 --plan-rate 200
expect_in "$tmp/err" "planned-force rate of 200 Hz is above the push's grid rate of 100 Hz" "the two rates are named"
expect_absent "$tmp/flag" "a plan rate above the grid's wrote an output"

# bench goes on past a bad file as every batch command does: the file listed, exit 1, the others timed; all bad is
# exit 2. A --json destination that cannot be written is refused before any work, nothing written.
expect_exit 1 "bench on a good and two bad files" -- limit "$bin" bench "$bad/huge_force/$stem.h5" "$good1" \
  "$bad/truncated/$stem.h5" --methods dob --json "$tmp/bench.json"
expect_in "$tmp/err" "FAILED $bad/huge_force/$stem.h5: stream 'ft_wrench' has fx 1e+300 N" "bench names the implausible file"
expect_in "$tmp/err" "FAILED $bad/truncated/$stem.h5: not a complete HDF5 file: it holds" "bench names the cut file"
expect_in "$tmp/err" "2 of 3 inputs failed" "bench counts the failures"
expect_in "$tmp/bench.json" '"failed": 2' "bench.json counts them"
expect_exit 2 "bench on a bad file alone" -- limit "$bin" bench "$bad/truncated/$stem.h5"
expect_in "$tmp/err" "bench: no push could be studied" "bench says nothing was studied"
expect_exit 2 "bench --json into a missing folder" -- limit "$bin" bench "$good1" --json "$tmp/nowhere/bench.json"
expect_in "$tmp/err" "$tmp/nowhere/bench.json: --json: its folder does not exist" "the --json destination is named"
[ ! -s "$tmp/out" ] && passed=$((passed + 1)) || { failed=$((failed + 1)); echo "FAIL: bench timed before refusing --json"; }

# simulate refuses a scenario that gives a push no command would read, and a folder as --config; nothing written.
printf '{"shape": "rect2", "initial_pose": [1e9, 0, 0]}\n' >"$tmp/far.json"
expect_exit 2 "simulate a start 1e6 km away" -- limit "$bin" simulate --config "$tmp/far.json" --out "$tmp/sim.h5"
expect_in "$tmp/err" "the simulated push is not one pushpred reads (stream 'tip_pose' has x 1e+09 m" "the reason is named"
expect_absent "$tmp/sim.h5" "no implausible recording written"
# Each numeric flag of simulate out of range (nan, inf, negative, 1e300) is refused naming the flag as typed, before
# anything is simulated: exit 2, nothing written. A negative or overlong seed is refused, not wrapped around.
while read -r flag value expected; do
  base=(--case 1)
  [ "$flag" = --case ] && base=()
  expect_exit 2 "simulate $flag $value" -- limit "$bin" simulate "${base[@]}" "$flag" "$value" --out "$tmp/sim.h5" </dev/null
  expect_in "$tmp/err" "$flag: $expected" "simulate $flag $value names the flag and the problem"
  expect_absent "$tmp/sim.h5" "simulate $flag $value writes nothing"
done <<'FLAGS'
--contact-mu inf must be a finite number in [0, 10], got inf
--contact-mu -1 must be a finite number in [0, 10], got -1
--mu nan must be a finite number in (0, 10], got nan
--mu 1e300 must be a finite number in (0, 10], got 1e+300
--seed -1 must be a whole number from 0 to 18446744073709551615, got '-1'
--seed 99999999999999999999999 must be a whole number from 0 to 18446744073709551615
--speed 1e300 must be a push speed in (0, 2] m/s, got 1e+300
--acceleration -1 must be a push acceleration in (0, 50] m/s^2, got -1
--side -1 must be a whole number from 0 to 999, got '-1'
--side 9 contact side 9 does not exist: this outline has sides 0..3
--position nan must be a place along the side in [0, 1], got nan
--angle inf must be within (-pi/2, pi/2) rad
--length 1e300 must be a push length in (0, 1] m, got 1e+300
--gap nan must be a gap in [-0.001, 0.05] m
--noise-scale 1e300 must be in [0, 100], got 1e+300
--jitter-scale -1 must be in [0, 10], got -1
--case 7 must be a whole number from 1 to 6, got '7'
--case nan must be a whole number from 1 to 6, got 'nan'
--effect force_offset=1e300 effect force_offset=1e+300: a sensor bias beyond 20 N
--effect viscous_friction=1e300 effect viscous_friction=1e+300: viscous friction must be in [0, 1e4] 1/s
--effect stribeck_friction=nan effect 'stribeck_friction=nan': amount must be finite
--effect inertia_mismatch=1e-300 effect inertia_mismatch=1e-300: the mass and inertia factor must be in [0.1, 10]
FLAGS
expect_exit 2 "simulate with a folder as --config" -- limit "$bin" simulate --config "$bad" --out "$tmp/sim.h5"
expect_in "$tmp/err" "$bad: is a folder, not a scenario file" "the folder is named"
expect_absent "$tmp/sim.h5" "nothing simulated from a folder"

# simulate --compare-real and --measure-real follow the same exit codes: 2 and no table when no input is usable,
# 1 when some failed.
for mode in --compare-real --measure-real; do
  expect_exit 2 "simulate $mode on bad files only" -- limit "$bin" simulate "$mode" "$bad/garbage/$stem.json" \
    "$tmp/odd/fifo.h5"
  expect_in "$tmp/err" "FAILED $bad/garbage/$stem.json: malformed JSON" "simulate $mode names the bad file"
  expect_in "$tmp/err" "2 of 2 inputs failed" "simulate $mode counts the failures"
  [ ! -s "$tmp/out" ] && passed=$((passed + 1)) || { failed=$((failed + 1)); echo "FAIL: simulate $mode printed a table"; }
  expect_exit 1 "simulate $mode on a good and a bad file" -- limit "$bin" simulate "$mode" "$good1" \
    "$bad/garbage/$stem.json"
  expect_in "$tmp/err" "1 of 2 inputs failed" "simulate $mode counts the failure"
done
finish
