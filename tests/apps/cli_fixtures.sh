#!/usr/bin/env bash
# The program end to end on the repository's own fixtures (tests/fixtures/rect1_abs: four simulated pushes of rect1
# on a support of friction 0.2), needing nothing outside the repository: inspect reads them, predict ranks the
# quasi-static model first, diagnose recovers the support's friction coefficient, learn and forecast-study forecast
# each push from the others better than the references.
set -u
bin=$1
fixtures=$2
source "$(dirname "$0")/cli_support.sh"

# json_number FILE PYTHON_EXPRESSION: prints the value of the expression over the file's JSON as `d`.
json_number() {
  python3 -c "import json, sys; d = json.load(open(sys.argv[1])); print($2)" "$1"
}
# below A B: A < B (floating point).
below() {
  python3 -c "import sys; sys.exit(0 if float(sys.argv[1]) < float(sys.argv[2]) else 1)" "$1" "$2"
}

expect_exit 0 "inspect the fixtures" -- "$bin" inspect "$fixtures"
expect_in "$tmp/out" "4 files read, 0 failed" "every fixture reads"

expect_exit 0 "predict on the fixtures" -- "$bin" predict "$fixtures" --out "$tmp/predict" --jobs 2
summary="$tmp/predict/summary.json"
qs=$(json_number "$summary" "d['aggregate']['quasi_static']['pos_mm_mean']")
dob=$(json_number "$summary" "d['aggregate']['dob']['pos_mm_mean']")
cv=$(json_number "$summary" "d['aggregate']['const_velocity']['pos_mm_mean']")
check "the quasi-static model ($qs mm) predicts better than the paper's dob ($dob mm)" below "$qs" "$dob"
check "the quasi-static model ($qs mm) predicts better than constant velocity ($cv mm)" below "$qs" "$cv"

# The simulator's support friction is 0.2: the diagnosis's Coulomb law recovers it within 5 %.
expect_exit 0 "diagnose the fixtures" -- "$bin" diagnose "$fixtures" --out "$tmp/diagnose"
mu=$(json_number "$tmp/diagnose/diagnosis.json" \
  "[e for e in d['effects'] if e['kind'] == 'coulomb_friction'][0]['parameters']['mu']['value']")
check "the fitted friction coefficient $mu is 0.2 within 5 %" \
  python3 -c "import sys; sys.exit(0 if abs(float(sys.argv[1]) - 0.2) <= 0.01 else 1)" "$mu"

# An object whose outline the shape table holds needs no data folder: run with none to be found.
expect_exit 0 "forecast-study on the fixtures" -- env PUSHPRED_DATA="$tmp/no-data-folder" "$bin" forecast-study \
  "$fixtures" --out "$tmp/forecast" --jobs 2
f="$tmp/forecast/summary.json"
forecast=$(json_number "$f" "d['methods']['forecast']['final_pos_mm_mean']")
still=$(json_number "$f" "d['methods']['not_moving']['final_pos_mm_mean']")
rigid=$(json_number "$f" "d['methods']['rigid_tip']['final_pos_mm_mean']")
check "the forecast's final position error ($forecast mm) is below not moving's ($still mm)" below "$forecast" "$still"
check "the forecast's final position error ($forecast mm) is below rigid tip-following's ($rigid mm)" \
  below "$forecast" "$rigid"

finish
