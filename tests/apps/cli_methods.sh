#!/usr/bin/env bash
# --methods, the same option with the same names and checks on every subcommand with per-method tables (predict,
# compare, reproduce, plot, bench): an unknown name is refused, named, with nothing written; the methods chosen are
# the ones in the output. diagnose has no --methods (its methods are the diagnosis's comparison, docs/prediction.md).
set -u
bin=$1
data=$2
source "$(dirname "$0")/cli_support.sh"

hex=$(abs_push 'shape=hex_a=0_v=50')

# An unknown name: the same error on every subcommand, exit 2, no output folder.
for sub in predict compare plot; do
  expect_exit 2 "$sub: an unknown method" -- "$bin" $sub "$hex" --out "$tmp/bad_$sub" --methods hold,magic
  expect_in "$tmp/err" "unknown prediction method 'magic' (known: dob, dob_velinit, simple, hold, const_velocity, quasi_static" \
    "$sub names the unknown method and the known ones"
  expect_absent "$tmp/bad_$sub" "$sub with an unknown method"
done
expect_exit 2 "reproduce: an unknown method" -- "$bin" reproduce --no-real --out "$tmp/bad_reproduce" --methods magic
expect_in "$tmp/err" "unknown prediction method 'magic'" "reproduce names the unknown method"
expect_absent "$tmp/bad_reproduce" "reproduce with an unknown method"
expect_exit 2 "bench: an unknown method" -- "$bin" bench "$hex" --methods magic
expect_in "$tmp/err" "unknown prediction method 'magic'" "bench names the unknown method"
# bench --cvode-prediction: both paths of the dob and simple models timed, and the dob model's two paths (the
# double integrator in closed form and by CVODE at rtol 1e-8) agreeing to well under a micrometre.
expect_exit 0 "bench with both prediction paths" -- "$bin" bench "$hex" --methods dob,simple --cvode-prediction \
  --json "$tmp/bench.json"
expect_in "$tmp/out" "the reference itself varies between runs" "bench says its reference moves between runs"
expect_in "$tmp/bench.json" '"reference_seconds_per_pass"' "bench writes the reference of every pass"
check "bench times both paths of both models and only the chosen methods, the dob model's paths within 1e-3 mm" \
  python3 -c '
import json, sys
doc = json.load(open(sys.argv[1]))
stages = {s["stage"] for s in doc["stages"]}
want = {"method dob", "method simple", "dob model, closed form", "dob model, CVODE", "simple model, closed form",
        "simple model, CVODE"}
missing, extra = want - stages, {s for s in stages if s.startswith("method ")} - want
difference = doc["cvode_prediction_largest_difference"]["dob model"]["position_mm"]
print("missing", sorted(missing), "extra", sorted(extra), "dob difference", difference, "mm")
sys.exit(0 if not missing and not extra and difference < 1e-3 else 1)' "$tmp/bench.json"
expect_exit 2 "a method listed twice" -- "$bin" compare "$hex" --out "$tmp/twice" --methods hold,hold
expect_in "$tmp/err" "method 'hold' listed twice" "the repeated method is named"
expect_absent "$tmp/twice" "compare with a repeated method"
expect_exit 2 "diagnose has no --methods" -- "$bin" diagnose "$hex" --out "$tmp/diag" --methods hold
expect_absent "$tmp/diag" "diagnose with --methods"

# compare: by default the methods that use the fitted relation; otherwise the ones chosen, two columns each.
expect_exit 0 "compare, default methods" -- "$bin" compare "$hex" --out "$tmp/c0" --estimators rls,batch
expect_in "$tmp/c0/compare.md" "per prediction method (\`dob\`, \`dob_velinit\`)" "compare says which methods"
expect_in "$tmp/c0/compare.md" "| dob pos err x/y [mm] | dob yaw err [deg] | dob_velinit pos err x/y [mm] |" \
  "compare's default columns"
expect_not_in "$tmp/c0/compare.md" "quasi_static" "compare's default leaves the other methods out"
expect_exit 0 "compare, chosen methods" -- "$bin" compare "$hex" --out "$tmp/c1" --estimators rls,batch \
  --methods quasi_static,dob
expect_in "$tmp/c1/compare.md" "| quasi_static pos err x/y [mm] | quasi_static yaw err [deg] | dob pos err x/y [mm] |" \
  "compare has the chosen methods' columns, in the order given"
expect_not_in "$tmp/c1/compare.md" "dob_velinit" "a method not chosen is not in compare.md"
# The methods predict apart: adding one changes no other's numbers.
dob_default=$(grep '^| rls |' "$tmp/c0/compare.md" | awk -F'|' '{print $11 "|" $12}')
dob_chosen=$(grep '^| rls |' "$tmp/c1/compare.md" | awk -F'|' '{print $13 "|" $14}')
if [ -n "$dob_default" ] && [ "$dob_default" = "$dob_chosen" ]; then passed=$((passed + 1)); else
  failed=$((failed + 1)); echo "FAIL: dob's errors depend on the other methods: '$dob_default' vs '$dob_chosen'"; fi

# predict: the chosen methods only, in summary.json and in tables.md.
expect_exit 0 "predict, chosen methods" -- "$bin" predict "$hex" --out "$tmp/p" --methods const_velocity,hold
expect_in "$tmp/p/summary.json" '"const_velocity"' "predict ran const_velocity"
expect_not_in "$tmp/p/summary.json" '"dob": {' "predict did not run dob"  # (the observer is also called dob)
expect_not_in "$tmp/p/summary.json" '"quasi_static"' "predict did not run quasi_static"
expect_not_in "$tmp/p/tables.md" "quasi_static" "tables.md has only the chosen methods"

# plot: one script per chosen method.
expect_exit 0 "plot, chosen methods" -- "$bin" plot "$hex" --out "$tmp/g" --methods hold,quasi_static
for m in hold quasi_static all; do
  if [ -s "$tmp/g/prediction_$m.gp" ]; then passed=$((passed + 1)); else failed=$((failed + 1)); echo "FAIL: plot: no prediction_$m.gp"; fi
done
expect_absent "$tmp/g/prediction_dob.gp" "plot drew a method not chosen"
expect_in "$tmp/out" "quasi_static" "plot prints the chosen method's errors"

# reproduce: the chosen methods in the per-method tables and summary.json, with the paper's dob and simple always.
expect_exit 0 "reproduce, chosen methods" -- "$bin" reproduce --no-real --out "$tmp/r" --methods hold
expect_in "$tmp/r/report.md" "Prediction methods: \`dob\`, \`simple\`, \`hold\`." "report.md says which methods ran"
expect_in "$tmp/r/report.md" "| hold |" "the per-method table has the chosen method"
expect_not_in "$tmp/r/summary.json" '"const_velocity"' "reproduce did not run a method not chosen"
expect_not_in "$tmp/r/summary.json" '"quasi_static"' "reproduce did not run quasi_static"
expect_in "$tmp/r/summary.json" '"simple"' "the paper's simple baseline always runs"
finish
