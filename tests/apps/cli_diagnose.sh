#!/usr/bin/env bash
# pushpred diagnose on real pushes: its outputs, --per-object over several objects, and every input
# a user can get wrong.
set -u
bin=$1
data=$2
source "$(dirname "$0")/cli_support.sh"

abs="$data/abs"
hex=$(ls "$abs"/motion_surface=abs_shape=hex_a=0_v=50_*.h5)
ellip=$(ls "$abs"/motion_surface=abs_shape=ellip1_a=0_v=50_*.h5)
frozen=$(ls "$abs"/motion_surface=abs_shape=rect1_*.h5 | head -2)

# shellcheck disable=SC2086
expect_exit 0 "diagnose the hex pushes at 50 mm/s" -- "$bin" diagnose $hex --out "$tmp/hex"
expect_in "$tmp/out" "held-out phases" "the terminal gets the before/after table"
for key in '"effects"' '"kind": "time_offset"' '"kind": "force_offset"' '"kind": "viscous_friction"' \
  '"kind": "stribeck_friction"' '"kind": "position_friction"' '"kind": "com_offset"' '"kind": "inertia_mismatch"' \
  '"kind": "initial_velocity"' '"kind": "coulomb_friction"' '"selected"' '"score"' '"parameters"' \
  '"error_before"' '"error_after"' '"error_references"' '"hold"' '"const_velocity"' '"pos_mm_mean"' \
  '"theta_deg_mean"' '"nothing_found"' '"findings"' '"error_base"' '"base_model"' '"negligible"' \
  '"floor"' '"floor_basis"' '"floor_context"' '"step_failures"'; do
  expect_in "$tmp/hex/diagnosis.json" "$key" "diagnosis.json holds $key"
done
# A non-finite number is written as null (JSON has no NaN): no value may be null but where the file says why (an
# effect with a note that it was not tested has no score; fewer than two measured sensor zeros have no spread, and
# fewer than two clear rests no rest score), and
# no bare NaN or Infinity token (which some parsers accept) may appear.
nulls=$(python3 -c '
import json, sys
def refuse(token): raise ValueError("bare " + token)
def nulls(v, at):
    if v is None: yield at
    elif isinstance(v, dict):
        for k, x in v.items(): yield from nulls(x, at + "." + k)
    elif isinstance(v, list):
        for i, x in enumerate(v): yield from nulls(x, at + "[%d]" % i)
def explained(d, at):
    if at == ".adequacy.force.sensor_zeros_spread_N":
        return d["adequacy"]["force"]["sensor_zeros_measured_pushes"] < 2
    if at == ".adequacy.rest.score":
        return not d["adequacy"]["rest"]["tested"]
    if at.startswith(".effects[") and at.endswith("].score"):
        e = d["effects"][int(at[len(".effects["):-len("].score")])]
        return not e["passed_test"] and "note" in e
    return False
try:
    d = json.load(open(sys.argv[1]), parse_constant=refuse)
    print(" ".join(at for at in nulls(d, "") if not explained(d, at)))
except ValueError as e: print(e)' "$tmp/hex/diagnosis.json")
if [ -z "$nulls" ]; then passed=$((passed + 1)); else failed=$((failed + 1))
  echo "FAIL: non-finite numbers in diagnosis.json: $nulls" | cut -c1-300; fi
expect_in "$tmp/hex/report.md" "## Prediction error on the held-out phases" "report.md has the before/after table"
expect_in "$tmp/hex/diagnosis.json" '"contact_compliance_m_N": 0.0' "the base model's rod is rigid by default"
# shellcheck disable=SC2086
expect_exit 0 "diagnose with the measured contact compliance" -- "$bin" diagnose $hex --measured-contact-compliance \
  --no-plots --out "$tmp/hex_compliant"
compliance=$(python3 -c 'import json, sys; print(json.load(open(sys.argv[1]))["contact_compliance_m_N"])' \
  "$tmp/hex_compliant/diagnosis.json")
if python3 -c 'import sys; c = float(sys.argv[1]); sys.exit(0 if 1e-5 < c < 1e-3 else 1)' "$compliance"; then
  passed=$((passed + 1))
else
  failed=$((failed + 1)); echo "FAIL: --measured-contact-compliance gives a rig's compliance (0.01-1 mm/N): $compliance"
fi
expect_in "$tmp/hex_compliant/report.md" "rod sinks" "the report's corrected model says how far its rod sinks"
expect_in "$tmp/hex/report.md" "## Candidate effects" "report.md lists every candidate"
expect_in "$tmp/hex/report.md" "plots/residuals.png" "report.md shows the residual plot"
expect_in "$tmp/hex/test_phase_errors.csv" "push,phase,t_s,dob_x_mm" "the errors over time are written"
[ -s "$tmp/hex/plots/residuals.png" ] && [ -s "$tmp/hex/plots/test_errors.png" ] && passed=$((passed + 1)) || {
  failed=$((failed + 1)); echo "FAIL: the residual and error plots are drawn"; }

# Several objects: refused without --per-object, diagnosed one by one with it.
# shellcheck disable=SC2086
expect_exit 2 "two objects without --per-object" -- "$bin" diagnose $hex $ellip --out "$tmp/mixed"
expect_in "$tmp/err" "pass --per-object" "the user is told about --per-object"
expect_absent "$tmp/mixed" "nothing written"
# shellcheck disable=SC2086
expect_exit 1 "--per-object with an object whose sensor is frozen" -- "$bin" diagnose $hex $ellip $frozen \
  --per-object --no-plots --out "$tmp/objects"
expect_in "$tmp/out" "2 of 3 objects diagnosed" "the diagnosed objects are counted"
expect_in "$tmp/err" "FAILED rect1_on_abs: diagnosis: no usable push among the 2 given (2 x force sensor frozen" \
  "the failed object is named with the reason"
expect_in "$tmp/objects/overview.md" "[hex_on_abs](hex_on_abs/report.md)" "the overview links each object's report"
expect_in "$tmp/objects/overview.md" "rect1_on_abs (2 pushes)" "the overview lists the object not diagnosed"
expect_in "$tmp/objects/overview.json" '"after_beats_both_references"' "overview.json compares with the references"
[ -s "$tmp/objects/ellip1_on_abs/diagnosis.json" ] && passed=$((passed + 1)) || {
  failed=$((failed + 1)); echo "FAIL: each object gets its own diagnosis.json"; }

# Inputs a user can get wrong: clear errors, non-zero exits, nothing written.
# shellcheck disable=SC2086
expect_exit 2 "only frozen sensors" -- "$bin" diagnose $frozen --out "$tmp/frozen"
expect_in "$tmp/err" "force sensor frozen" "the reason is named"
expect_absent "$tmp/frozen" "nothing written"
# shellcheck disable=SC2086
expect_exit 2 "an unknown effect to exclude" -- "$bin" diagnose $hex --exclude teapot_effect --out "$tmp/x1"
expect_in "$tmp/err" "teapot_effect" "the unknown effect is named"
# shellcheck disable=SC2086
expect_exit 2 "an unknown relation estimator" -- "$bin" diagnose $hex --estimator magic --out "$tmp/x2"
expect_in "$tmp/err" "magic" "the unknown estimator is named"
expect_exit 2 "an unknown flag" -- "$bin" diagnose --frobnicate $hex --out "$tmp/x3"
expect_exit 2 "too few intervals" -- "$bin" diagnose --intervals 2 $hex --out "$tmp/x4"
printf 'not a recording' > "$tmp/junk.h5"
expect_exit 2 "nothing readable" -- "$bin" diagnose "$tmp/junk.h5" "$tmp/missing.h5" --out "$tmp/x5"
expect_in "$tmp/err" "FAILED $tmp/missing.h5: file does not exist" "the missing file is named"
expect_absent "$tmp/x5" "nothing written"
# shellcheck disable=SC2086
expect_exit 1 "a bad file among good ones" -- "$bin" diagnose $hex "$tmp/junk.h5" --no-plots --out "$tmp/x6"
expect_in "$tmp/err" "FAILED $tmp/junk.h5: neither an HDF5 nor a JSON recording" "the bad file is named"
expect_in "$tmp/x6/diagnosis.json" '"error_after"' "the good files are still diagnosed"
finish
