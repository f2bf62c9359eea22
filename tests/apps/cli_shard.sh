#!/usr/bin/env bash
# --shard I/N and `pushpred merge`: the partial outputs of every shard, merged, are the output of one run
# byte for byte (diff -r), with the same stdout, failure list and exit code; bad shard specs, --shard on a
# subcommand that cannot split (it does not list --shard), and parts that are not every shard of one run are refused
# with exit 2 and no output.
# The same for validate-diagnosis's trials and diagnose --per-object's objects.
set -u
bin=$1
data=$2
source "$(dirname "$0")/cli_support.sh"

batch_files  # the missing file goes into a shard's partial output and the merged failure list

"$bin" predict "${files[@]}" --out "$tmp/whole" --jobs 1 >"$tmp/whole.out" 2>"$tmp/whole.err"
whole_code=$?
check "the whole run exits 1 (the missing file)" [ "$whole_code" -eq 1 ]
sed -i "s#$tmp/whole#OUT#g" "$tmp/whole.out"

# merged N NAME: runs shards 1/N ... N/N (the last ones with 2 jobs), merges them in reverse order into $tmp/NAME and
# compares everything with the whole run.
merged() {
  local n=$1 name=$2 parts=()
  for ((i = 1; i <= n; i++)); do
    "$bin" predict "${files[@]}" --out "$tmp/$name.part$i" --shard "$i/$n" --jobs $((i % 2 + 1)) >"$tmp/$name.part$i.out" 2>&1
    check "$name: shard $i/$n wrote its partial output" [ -f "$tmp/$name.part$i/partial.json" ]
    check "$name: shard $i/$n wrote no summary" [ ! -e "$tmp/$name.part$i/summary.json" ]
    parts=("$tmp/$name.part$i" "${parts[@]}")
  done
  "$bin" merge --out "$tmp/$name" "${parts[@]}" >"$tmp/$name.out" 2>"$tmp/$name.err"
  local code=$?
  check "$name: merge exits as the whole run ($whole_code), got $code" [ "$code" -eq "$whole_code" ]
  expect_same_tree "$tmp/whole" "$tmp/$name" "$name: merged output differs from the whole run"
  sed -i "s#$tmp/$name#OUT#g" "$tmp/$name.out"
  check "$name: merge prints what the whole run prints" cmp -s "$tmp/whole.out" "$tmp/$name.out"
  check "$name: the same failures are listed" diff <(grep -E '^FAILED' "$tmp/whole.err") <(grep -E '^FAILED' "$tmp/$name.err")
}

merged 2 two
# The sorted list dealt out: shard 1/2 takes the 1st, 3rd and 5th of the sorted names.
mapfile -t sorted < <(printf '%s\n' "${files[@]}" | LC_ALL=C sort)
# Where $tmp/missing.h5 and the failing rect1 push fall in that order depends on where mktemp and the data live, so
# an input counts as shard 1's when it has a prediction there or is listed there as a failure.
taken_by_part1() {  # taken_by_part1 INPUT: shard 1/2 predicted INPUT or listed it as failed
  local stem
  stem=$(basename "$1" .h5)
  # partial.json is indented, its items' results compact: a key may or may not have a space after its colon.
  [ -f "$tmp/two.part1/predictions/$stem.csv" ] || grep -qF -e "\"source\": \"$1\"" -e "\"source\":\"$1\"" \
    "$tmp/two.part1/partial.json"
}
for k in 0 2 4; do
  check "shard 1/2 took sorted input $k ($(basename "${sorted[$k]}"))" taken_by_part1 "${sorted[$k]}"
done
for k in 1 3 5; do
  check "shard 1/2 left sorted input $k ($(basename "${sorted[$k]}")) to shard 2/2" eval '! taken_by_part1 "${sorted[$k]}"'
done
expect_in "$tmp/whole/summary.json" '"failures"' "the whole run lists failures"
expect_in "$tmp/two.part1.out" "partial output in" "a shard says where its partial output is"
merged 1 one     # --shard 1/1 is a partial output too (an array job of one task), merged alone
merged 4 four
merged 8 eight   # more shards than inputs: two shards have nothing to do

# Bad shard specs: a clear error naming --shard, exit 2, nothing written.
for spec in 0/2 3/2 x 1/0 2 1/2/3 ""; do
  expect_exit 2 "--shard '$spec' refused" -- "$bin" predict "${files[0]}" --out "$tmp/bad" --shard "$spec"
  expect_in "$tmp/err" "--shard '$spec'" "the error names --shard '$spec'"
  check "--shard '$spec' wrote nothing" [ ! -e "$tmp/bad" ]
done

# Subcommands that cannot split do not list --shard (pushpred inspect --help): given, it is an unknown option, exit 2,
# before anything is read or written.
for sub in inspect fit-pid compare; do
  "$bin" "$sub" --help >"$tmp/help" 2>&1
  expect_not_in "$tmp/help" "--shard" "$sub --help does not list --shard"
done
expect_exit 2 "inspect --shard refused" -- "$bin" inspect "${files[0]}" --shard 1/2
expect_in "$tmp/err" "--shard" "inspect names --shard"
expect_exit 2 "fit-pid --shard refused" -- "$bin" fit-pid "${files[0]}" --out "$tmp/bad" --shard 1/2
check "fit-pid --shard wrote nothing" [ ! -e "$tmp/bad" ]
expect_exit 2 "compare --shard refused" -- "$bin" compare "${files[0]}" --out "$tmp/bad" --shard 1/2
# diagnose splits only --per-object runs: one object is one unit.
expect_exit 2 "diagnose --shard without --per-object refused" -- "$bin" diagnose "${files[0]}" --out "$tmp/bad" \
  --shard 1/2
expect_in "$tmp/err" "--shard 1/2: \`diagnose\` splits its work only with --per-object" "diagnose says why"
check "no refused subcommand wrote anything" [ ! -e "$tmp/bad" ]

# validate-diagnosis: trial k goes to shard k mod N + 1; two trials as 2 and 3 shards (one with none), merged.
validate=(validate-diagnosis --trials 1 --kinds none,force_offset --min-pushes 4 --max-pushes 4 --quick-base --seed 9000
          --jobs 1)
"$bin" "${validate[@]}" --out "$tmp/vwhole" >"$tmp/vwhole.out" 2>/dev/null
vcode=$?
sed -i "s#$tmp/vwhole#OUT#g" "$tmp/vwhole.out"
for n in 2 3; do
  parts=()
  for ((i = 1; i <= n; i++)); do
    "$bin" "${validate[@]}" --out "$tmp/v$n.part$i" --shard "$i/$n" >/dev/null 2>&1
    parts+=("$tmp/v$n.part$i")
  done
  "$bin" merge --out "$tmp/v$n" "${parts[@]}" >"$tmp/v$n.out" 2>/dev/null
  code=$?
  check "validate-diagnosis $n shards: merge exits as the whole run ($vcode), got $code" [ "$code" -eq "$vcode" ]
  expect_same_tree "$tmp/vwhole" "$tmp/v$n" "validate-diagnosis $n shards: merged output differs"
  sed -i "s#$tmp/v$n#OUT#g" "$tmp/v$n.out"
  check "validate-diagnosis $n shards: merge prints what the whole run prints" cmp -s "$tmp/vwhole.out" "$tmp/v$n.out"
done
expect_in "$tmp/v2.part1/partial.json" '"true_kind":"none"' "shard 1/2 ran trial 0 (clean)"
expect_not_in "$tmp/v2.part1/partial.json" '"true_kind":"force_offset"' "shard 1/2 ran trial 1"
expect_exit 2 "validate-diagnosis --shard 3/2 refused" -- "$bin" "${validate[@]}" --out "$tmp/bad" --shard 3/2
expect_exit 2 "a predict part merged with a validate-diagnosis part" -- "$bin" merge --out "$tmp/m" "$tmp/two.part1" \
  "$tmp/v2.part2"
expect_in "$tmp/err" "not of \`predict\`" "the mixed parts are named"
check "no refused run wrote anything" [ ! -e "$tmp/bad" ]

# diagnose --per-object: the unit is one object (a diagnosis each); every shard reads every file, the objects sorted
# by name are dealt out. Four objects (one fails: its one push has a frozen force sensor) and a missing file, whole
# and as 1, 2 and 3 shards merged.
dfiles=()
for pattern in 'shape=hex_a=0_v=50' 'shape=ellip1_a=0_v=50' 'shape=ellip3_a=0_v=75'; do
  mapfile -t -O "${#dfiles[@]}" dfiles < <(ls "$data"/abs/*"$pattern"*.h5 | head -2)
done
dfiles+=("$(abs_push 'shape=rect1_')" "$tmp/missing.h5")
diagnose=(diagnose --per-object --no-plots --quick-base --intervals 3 --jobs 1)
"$bin" "${diagnose[@]}" "${dfiles[@]}" --out "$tmp/dwhole" >"$tmp/dwhole.out" 2>"$tmp/dwhole.err"
dcode=$?
check "diagnose --per-object: the whole run exits 1 (a failed object, a missing file), got $dcode" [ "$dcode" -eq 1 ]
expect_in "$tmp/dwhole.out" "3 of 4 objects diagnosed (7 pushes read)" "the whole run diagnosed three objects"
sed -i "s#$tmp/dwhole#OUT#g" "$tmp/dwhole.out"
for n in 1 2 3; do
  parts=()
  for ((i = 1; i <= n; i++)); do
    "$bin" "${diagnose[@]}" "${dfiles[@]}" --out "$tmp/d$n.part$i" --shard "$i/$n" >"$tmp/d$n.part$i.out" 2>&1
    check "diagnose $n shards: shard $i/$n wrote its partial output" [ -f "$tmp/d$n.part$i/partial.json" ]
    check "diagnose $n shards: shard $i/$n wrote no overview" [ ! -e "$tmp/d$n.part$i/overview.md" ]
    parts=("$tmp/d$n.part$i" "${parts[@]}")
  done
  "$bin" merge --out "$tmp/d$n" "${parts[@]}" >"$tmp/d$n.out" 2>"$tmp/d$n.err"
  code=$?
  check "diagnose $n shards: merge exits as the whole run ($dcode), got $code" [ "$code" -eq "$dcode" ]
  expect_same_tree "$tmp/dwhole" "$tmp/d$n" "diagnose $n shards: merged output differs"
  sed -i "s#$tmp/d$n#OUT#g" "$tmp/d$n.out"
  check "diagnose $n shards: merge prints what the whole run prints" cmp -s "$tmp/dwhole.out" "$tmp/d$n.out"
  check "diagnose $n shards: the same failures are listed" \
    diff <(grep -E '^(FAILED|LEFT OUT|[0-9]+ of)' "$tmp/dwhole.err") <(grep -E '^(FAILED|LEFT OUT|[0-9]+ of)' "$tmp/d$n.err")
done
expect_in "$tmp/dwhole.err" "FAILED $tmp/missing.h5" "the missing file is listed"
expect_in "$tmp/dwhole.err" "FAILED rect1_on_abs" "the object that cannot be diagnosed is listed"
# The objects sorted: ellip1, ellip3, hex, rect1; shard 1/2 takes the 1st and 3rd.
check "diagnose shard 1/2 took ellip1" [ -f "$tmp/d2.part1/ellip1_on_abs/diagnosis.json" ]
check "diagnose shard 1/2 took hex" [ -f "$tmp/d2.part1/hex_on_abs/diagnosis.json" ]
check "diagnose shard 1/2 left ellip3 to shard 2/2" [ ! -e "$tmp/d2.part1/ellip3_on_abs" ]
check "diagnose shard 2/2 took ellip3" [ -f "$tmp/d2.part2/ellip3_on_abs/diagnosis.json" ]
expect_in "$tmp/d2.part1.out" "partial output in" "a diagnose shard says where its partial output is"
expect_exit 2 "diagnose --per-object --shard 3/2 refused" -- "$bin" "${diagnose[@]}" "${dfiles[@]}" --out "$tmp/bad" \
  --shard 3/2
expect_in "$tmp/err" "--shard '3/2'" "the error names --shard"
check "the refused diagnose wrote nothing" [ ! -e "$tmp/bad" ]
"$bin" "${diagnose[@]}" "${dfiles[@]}" --out "$tmp/dopt.part2" --shard 2/2 --bic-threshold 12 >/dev/null 2>&1
expect_exit 2 "diagnose shards run with other options" -- "$bin" merge --out "$tmp/m" "$tmp/d2.part1" "$tmp/dopt.part2"
expect_in "$tmp/err" "other options" "other diagnose options are named"
"$bin" "${diagnose[@]}" "${dfiles[@]:0:4}" --out "$tmp/dother.part2" --shard 2/2 >/dev/null 2>&1
expect_exit 2 "diagnose shards given other inputs" -- "$bin" merge --out "$tmp/m" "$tmp/d2.part1" "$tmp/dother.part2"
expect_in "$tmp/err" "other inputs" "other diagnose inputs are named"
expect_exit 2 "a diagnose part merged with a predict part" -- "$bin" merge --out "$tmp/m" "$tmp/d2.part1" \
  "$tmp/two.part2"
check "no refused diagnose merge wrote anything" [ ! -e "$tmp/m" ]
# No object can be diagnosed (every push has a frozen sensor): the merge, like the whole run, exits 2, writes nothing.
mapfile -t frozen < <(ls "$data"/abs/*shape=rect1_*.h5 | head -2)
"$bin" "${diagnose[@]}" "${frozen[@]}" --out "$tmp/fwhole" >/dev/null 2>"$tmp/fwhole.err"
check "diagnose --per-object of frozen pushes only exits 2" [ $? -eq 2 ]
"$bin" "${diagnose[@]}" "${frozen[@]}" --out "$tmp/f.part1" --shard 1/1 >/dev/null 2>&1
expect_exit 2 "the merge of a run with no object diagnosed" -- "$bin" merge --out "$tmp/f" "$tmp/f.part1"
check "it lists what the whole run lists" diff "$tmp/fwhole.err" "$tmp/err"
check "the whole run wrote nothing" [ ! -e "$tmp/fwhole" ]
check "the merge wrote nothing" [ ! -e "$tmp/f" ]

# Parts that are not every shard of one run.
expect_exit 2 "a missing shard" -- "$bin" merge --out "$tmp/m" "$tmp/two.part1"
expect_in "$tmp/err" "shard 2/2 missing" "the missing shard is named"
expect_exit 2 "a shard given twice" -- "$bin" merge --out "$tmp/m" "$tmp/two.part1" "$tmp/two.part1"
expect_in "$tmp/err" "as is" "the repeated shard is named"
expect_exit 2 "shards of two splits" -- "$bin" merge --out "$tmp/m" "$tmp/two.part1" "$tmp/four.part2"
expect_exit 2 "a folder that is no partial output" -- "$bin" merge --out "$tmp/m" "$tmp/whole" "$tmp/two.part2"
expect_in "$tmp/err" "no partial.json" "a whole run's folder is not a part"
"$bin" predict "${files[@]:0:3}" --out "$tmp/other.part2" --shard 2/2 --jobs 1 >/dev/null 2>&1
expect_exit 2 "shards given other inputs" -- "$bin" merge --out "$tmp/m" "$tmp/two.part1" "$tmp/other.part2"
expect_in "$tmp/err" "other inputs" "other inputs are named"
"$bin" predict "${files[@]}" --out "$tmp/opt.part2" --shard 2/2 --jobs 1 --intervals 3 >/dev/null 2>&1
expect_exit 2 "shards run with other options" -- "$bin" merge --out "$tmp/m" "$tmp/two.part1" "$tmp/opt.part2"
expect_in "$tmp/err" "other options" "other options are named"
cp -r "$tmp/two.part2" "$tmp/broken.part2"
rm "$tmp"/broken.part2/by-input/*.csv
expect_exit 2 "a part whose file is gone" -- "$bin" merge --out "$tmp/m" "$tmp/two.part1" "$tmp/broken.part2"
expect_in "$tmp/err" "is missing" "the missing file is named"
check "no refused merge wrote anything" [ ! -e "$tmp/m" ]
expect_exit 2 "--out is one of the parts" -- "$bin" merge --out "$tmp/two.part1" "$tmp/two.part1" "$tmp/two.part2"
check "the part is still there" [ -f "$tmp/two.part1/partial.json" ]
finish
