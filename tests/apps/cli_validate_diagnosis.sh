#!/usr/bin/env bash
# pushpred validate-diagnosis: a tiny blind validation writes its report and JSON with its documented keys; bad
# arguments give a clear error, exit 2 and no output.
set -u
bin=$1
source "$(dirname "$0")/cli_support.sh"

expect_exit 0 "a tiny validation" -- "$bin" validate-diagnosis --trials 1 --kinds none,force_offset --min-pushes 4 \
  --max-pushes 4 --quick-base --seed 9000 --jobs 2 --out "$tmp/v"
expect_in "$tmp/out" "nothing named on clean" "the terminal gets the summary"
for key in '"trials"' '"true_kind": "none"' '"true_kind": "force_offset"' '"named"' '"negligible"' '"floor"' \
  '"floor_multiple"' '"fitted_amount"' '"before"' '"base"' '"after"' '"hold"' '"const_velocity"' '"summary"' \
  '"clean_nothing_named"' '"named_at_twice_floor"'; do
  expect_in "$tmp/v/validation.json" "$key" "validation.json holds $key"
done
for section in "## Targets" "## Confusion matrix" "## Detection rate against the amount" \
  "## False findings on clean trials" "## Held-out prediction error"; do
  expect_in "$tmp/v/validation.md" "$section" "validation.md has $section"
done

# --hide: the kind is simulated but not a candidate; the report gives the honesty rates.
expect_exit 0 "a tiny honesty validation" -- "$bin" validate-diagnosis --trials 1 --hide compliant_pusher \
  --min-pushes 4 --max-pushes 4 --quick-base --seed 9100 --jobs 2 --out "$tmp/h"
for key in '"hide"' '"true_kind": "compliant_pusher"' '"hidden": true' '"adequacy"' '"hidden_none_named"' \
  '"clean_explained"' '"preloaded_pushes"' '"draw_preloads": true' '"draw_sensor_offsets": true' \
  '"sensor_offset_spread_N": 0.06'; do
  expect_in "$tmp/h/validation.json" "$key" "the honesty run's validation.json holds $key"
done
expect_in "$tmp/h/validation.md" "Hidden from the diagnosis's catalogue (simulated, not a candidate): compliant_pusher" \
  "validation.md names the hidden kind"
expect_in "$tmp/h/validation.md" "no other kind named" "validation.md gives the hidden kind's no-other-kind rate"
expect_exit 2 "an unknown hidden kind" -- "$bin" validate-diagnosis --trials 1 --hide bogus --out "$tmp/bad4"
expect_in "$tmp/err" "unknown effect 'bogus'" "the error names the hidden kind"
expect_absent "$tmp/bad4" "output written for a bad hidden kind"

expect_exit 2 "an unknown kind" -- "$bin" validate-diagnosis --trials 1 --kinds bogus --out "$tmp/bad1"
expect_in "$tmp/err" "unknown effect 'bogus'" "the error names the kind"
expect_absent "$tmp/bad1" "output written for a bad kind"
expect_exit 2 "too few pushes" -- "$bin" validate-diagnosis --trials 1 --min-pushes 1 --out "$tmp/bad2"
expect_absent "$tmp/bad2" "output written for bad pushes"
expect_exit 2 "too many pushes" -- "$bin" validate-diagnosis --trials 1 --max-pushes 100000 --out "$tmp/bad5"
expect_in "$tmp/err" "--max-pushes must be at most 100" "the error names the flag and its bound"
expect_absent "$tmp/bad5" "output written for too many pushes"
expect_in "$tmp/v/validation.json" '"floor_margin_std": 1.0' "validation.json records the floor margin"
expect_in "$tmp/v/validation.md" "floor margin 1.0 standard error(s)" "validation.md states the floor margin"
for margin in -1 nan; do
  expect_exit 2 "a floor margin of $margin" -- "$bin" validate-diagnosis --trials 1 --floor-margin "$margin" --out "$tmp/bad3"
  expect_in "$tmp/err" "--floor-margin: must be a finite number >= 0, got '$margin'" "the error names flag and value ($margin)"
  expect_absent "$tmp/bad3" "output written for a floor margin of $margin"
done
expect_in "$tmp/h/validation.md" "force-sensor offset (sd 0.06 N per axis)" "validation.md states the sensor zeros' spread"
for spread in -0.1 nan; do
  expect_exit 2 "a sensor-offset spread of $spread" -- "$bin" validate-diagnosis --trials 1 \
    --sensor-offset-spread "$spread" --out "$tmp/bad5"
  expect_in "$tmp/err" "--sensor-offset-spread: must be a finite number >= 0, got '$spread'" \
    "the error names flag and value ($spread)"
  expect_absent "$tmp/bad5" "output written for a sensor-offset spread of $spread"
done
expect_in "$tmp/h/validation.md" "the diagnosis assumes a zero spread of 0.10 N per axis" \
  "validation.md states the zero spread the diagnosis assumes"
for spread in -0.1 nan; do
  expect_exit 2 "a sensor-zero spread of $spread" -- "$bin" validate-diagnosis --trials 1 \
    --sensor-zero-spread "$spread" --out "$tmp/bad6"
  expect_in "$tmp/err" "--sensor-zero-spread: must be a finite number >= 0, got '$spread'" \
    "the error names flag and value ($spread)"
  expect_absent "$tmp/bad6" "output written for a sensor-zero spread of $spread"
done
# A seed is a whole number from 0 (a negative one wrapped around to 2^64 - 1); the pushes per trial and the spreads of
# the sensor zeros are bounded (a spread of 1e300 N failed every trial), each error naming its flag.
while read -r flag value expected; do
  expect_exit 2 "validate-diagnosis $flag $value" -- "$bin" validate-diagnosis --trials 1 "$flag" "$value" \
    --out "$tmp/bad7" </dev/null
  expect_in "$tmp/err" "$expected" "validate-diagnosis $flag $value names the flag and the problem"
  expect_absent "$tmp/bad7" "output written for $flag $value"
done <<'FLAGS'
--seed -1 --seed: must be a whole number from 0 to 18446744073709551615, got '-1'
--seed 99999999999999999999999 --seed: must be a whole number from 0 to 18446744073709551615
--min-pushes -1 --min-pushes must be at least 2 (got -1)
--sensor-offset-spread 1e300 --sensor-offset-spread must be at most 2 N (got 1e+300)
--sensor-zero-spread 1e300 --sensor-zero-spread: must be a finite number in [0, 20], got '1e300'
FLAGS
finish
