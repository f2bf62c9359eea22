#!/usr/bin/env bash
# pushpred learn, forecast, forecast-study and limit-surface-study: outputs, the excluded frozen sensors, --jobs, bad
# flags and bad files (a clear error naming the file, exit 2, nothing written).
set -u
bin=$1
data=$2
source "$(dirname "$0")/cli_support.sh"

hex=$(ls "$data"/abs/motion_surface=abs_shape=hex_*.h5 | head -6)
frozen=$(abs_push 'shape=rect1_')

# learn: one object's model from its pushes; a frozen sensor is left out, by name.
# shellcheck disable=SC2086
expect_exit 0 "learn hex from six pushes and a frozen rect1" -- "$bin" learn $hex "$frozen" --out "$tmp/hex.json" --jobs 2
expect_in "$tmp/out" "learned hex on abs from 6 pushes" "the learned pushes are counted"
expect_in "$tmp/err" "excluded $(basename "$frozen" .h5): force sensor frozen" "the frozen sensor is named"
expect_in "$tmp/hex.json" '"format": "pushpred-object-model"' "the object file says its format"
expect_in "$tmp/hex.json" '"version": 7' "the object file says its version"
expect_in "$tmp/hex.json" '"limit_surface": "ellipsoid"' "the ellipsoidal limit surface by default"
expect_in "$tmp/hex.json" '"push_to_push_sd"' "the object file holds the push-to-push spread"
expect_in "$tmp/hex.json" '"parameter_trend"' "the object file holds the parameter trend"
expect_in "$tmp/out" "parameter trend over the plan: none" "no trend by default"
expect_in "$tmp/out" "residual correction: leave-one-out final errors" "the residual correction by default"
expect_in "$tmp/hex.json" '"loo_final_error"' "the object file holds each push's leave-one-out error"
# shellcheck disable=SC2086
expect_exit 0 "learn hex without the residual correction" -- "$bin" learn $hex --residual-correction none \
  --out "$tmp/hex-plain.json" --jobs 2
expect_in "$tmp/hex-plain.json" '"applied": false' "the object file says the correction is not applied"
expect_in "$tmp/out" "residual correction: none" "learn says it does not correct"
expect_in "$tmp/out" "pusher friction: fitted per push" "the rod friction fitted per push by default"
# shellcheck disable=SC2086
expect_exit 0 "learn hex with the measured rod friction" -- "$bin" learn $hex --pusher-friction measured \
  --out "$tmp/hex-measured.json" --jobs 2
expect_in "$tmp/out" "pusher friction: measured: " "learn says the rod friction is the measured one"
expect_in "$tmp/hex-measured.json" '"method": "measured: ' "the object file says where the rod friction comes from"
# shellcheck disable=SC2086
expect_exit 0 "learn hex with the trend chosen" -- "$bin" learn $hex --trend chosen --out "$tmp/hex-trend.json" --jobs 2
expect_in "$tmp/out" "parameter trend over the plan" "learn says whether it took a trend"
# shellcheck disable=SC2086
expect_exit 0 "learn hex on the outline's limit surface" -- "$bin" learn $hex --limit-surface outline \
  --centre-of-friction centroid --out "$tmp/hex-outline.json" --jobs 2
expect_in "$tmp/hex-outline.json" '"limit_surface": "outline"' "the object file keeps the outline's limit surface"
expect_in "$tmp/out" "limit surface: the outline's pressure" "learn says which limit surface"
expect_in "$tmp/out" "pressure rim weight: " "learn says the pressure's rim weight"
expect_in "$tmp/hex-outline.json" '"rim_weight"' "the object file keeps the pressure's rim weight"
# The rim weight learned always: its jackknife standard error's refits run on the jobs, the file the same for any.
for j in 1 2; do
  # shellcheck disable=SC2086
  expect_exit 0 "learn hex's rim weight with --jobs $j" -- "$bin" learn $hex --limit-surface outline \
    --centre-of-friction centroid --pressure-shape learned --out "$tmp/hex-rim-$j.json" --jobs $j
done
expect_in "$tmp/out" "(jackknife standard error), learned from 6 pushes" "learn says how w's standard error is had"
check "the learned rim weight's file is the same for --jobs 1 and 2" cmp "$tmp/hex-rim-1.json" "$tmp/hex-rim-2.json"
expect_in "$tmp/hex-rim-1.json" "at the lower bound of its range" "a rim weight at its bound is said to be there"
# shellcheck disable=SC2086
expect_exit 2 "an unknown pressure shape" -- "$bin" learn $hex --limit-surface outline --pressure-shape cone \
  --out "$tmp/cone.json"
expect_exit 0 "forecast on the outline's limit surface" -- "$bin" forecast --model "$tmp/hex-outline.json" \
  --object-pose 0,0,0 --tip -66,10 --direction 10 --speed 50 --out "$tmp/f-outline"
check "the outline forecast wrote forecast.json" test -s "$tmp/f-outline/forecast.json"
# shellcheck disable=SC2086
expect_exit 2 "an unknown limit surface" -- "$bin" learn $hex --limit-surface cuboid --out "$tmp/cuboid.json"
expect_in "$tmp/err" "cuboid" "the unknown limit surface is named"
expect_absent "$tmp/cuboid.json" "no object file for an unknown limit surface"
# shellcheck disable=SC2086
expect_exit 2 "learn from two objects at once" -- "$bin" learn $hex "$(abs_push 'shape=ellip1_')" --out "$tmp/two.json"
expect_in "$tmp/err" "several objects" "the mix is named"
expect_absent "$tmp/two.json" "no object file from two objects"
expect_exit 2 "learn into a missing folder" -- "$bin" learn $hex --out "$tmp/nowhere/hex.json"
expect_in "$tmp/err" "$tmp/nowhere/hex.json: its folder does not exist" "the destination is named"
expect_exit 2 "an own outline without mass" -- "$bin" learn $hex --circle 0.05 --out "$tmp/disc.json"
expect_in "$tmp/err" "--mass" "the missing mass is named"
expect_absent "$tmp/disc.json" "no object file without a mass"

# shellcheck disable=SC2086
expect_exit 2 "an ellipse of three semi-axes" -- "$bin" learn $hex --ellipse 0.05,0.03,0.01 --mass 1 --inertia 0.001 \
  --out "$tmp/e3.json"
expect_in "$tmp/err" "--ellipse: expected A,B" "the ellipse is named"
# shellcheck disable=SC2086
expect_exit 2 "--name without an own outline" -- "$bin" learn $hex --name foo --out "$tmp/foo.json"
expect_in "$tmp/err" "--name goes with an outline of one's own" "the lone --name is named"
# shellcheck disable=SC2086
expect_exit 2 "an empty --out" -- "$bin" learn $hex --out ""
expect_in "$tmp/err" "--out: empty path" "the empty --out is named"
for f in e3 foo; do expect_absent "$tmp/$f.json" "no object file ($f)"; done
# An own outline, mass and inertia no pushed tabletop object has, and a name that is not letters and digits, are
# refused naming the flag (reading/physical_bounds.hpp): before any push is read, nothing written.
printf 'x_m,y_m\n-50,-50\n50,-50\n50,50\n-50,50\n' >"$tmp/huge.csv"
while IFS='|' read -r what args expected; do
  # shellcheck disable=SC2086
  expect_exit 2 "learn with $what" -- "$bin" learn $hex $args --out "$tmp/absurd.json" </dev/null
  expect_in "$tmp/err" "$expected" "learn with $what: the flag and the problem are named"
  expect_absent "$tmp/absurd.json" "no object file from $what"
done <<ABSURD
a_100_m_polygon|--outline=$tmp/huge.csv --mass=1 --inertia=0.001|--outline $tmp/huge.csv: the outline is 141 m across, more than the 2 m
a_1e9_m_circle|--circle=1e9 --mass=1 --inertia=0.001|--circle: the outline is 2e+09 m across, more than the 2 m
a_100_m_ellipse|--ellipse=50,30 --mass=1 --inertia=0.001|--ellipse: the outline is 100 m across
a_0.2_mm_sliver|--ellipse=0.05,0.0001 --mass=1 --inertia=0.001|--ellipse: the outline is 0.2 mm wide at its narrowest, less than the 1 mm
a_1e9_kg_disc|--circle=0.05 --mass=1e9 --inertia=0.001|--mass: 1e+09 kg is 1.27e+11 kg per m^2
a_1e-9_kg_disc|--circle=0.05 --mass=1e-9 --inertia=1e-12|--mass: 1e-09 kg is 1.27e-07 kg per m^2
an_inertia_beyond_the_outline|--circle=0.05 --mass=1 --inertia=1e6|--inertia: 1e+06 kg m^2 with a mass of 1 kg gives a radius of gyration
an_inertia_of_a_point|--circle=0.05 --mass=1 --inertia=1e-12|--inertia: 1e-12 kg m^2 with a mass of 1 kg
ABSURD
for name in "my box" "a/b" "it's" "hex_2"; do
  # shellcheck disable=SC2086
  expect_exit 2 "learn --name '$name'" -- "$bin" learn $hex --circle 0.05 --mass 1 --inertia 0.001 --name "$name" \
    --out "$tmp/named.json"
  expect_in "$tmp/err" "--name: '$name' is not a name an object may have: letters and digits only" "'$name' is refused"
  expect_absent "$tmp/named.json" "no object file named '$name'"
done

# One's own outline: the hexagon given as a polygon file with its mass and inertia learns what the shape table's does.
python3 -c "
import math
print('x_m,y_m')
for k in range(6): print(f'{0.0605 * math.cos(k * math.pi / 3):.9f},{0.0605 * math.sin(k * math.pi / 3):.9f}')
" >"$tmp/myhex.csv"
# shellcheck disable=SC2086
expect_exit 0 "learn with one's own polygon" -- "$bin" learn $hex --outline "$tmp/myhex.csv" --mass 0.9827 \
  --inertia 0.001497 --name myhex --out "$tmp/myhex.json"
expect_in "$tmp/myhex.json" '"kind": "polygon"' "the own outline is kept as a polygon"
expect_in "$tmp/myhex.json" '"name": "myhex"' "the own object's name"
check "the own polygon learns the shape table's mu_p (to 1 %)" python3 -c "
import json, sys
a = json.load(open('$tmp/hex.json'))['parameters']['pusher_friction']['value']
b = json.load(open('$tmp/myhex.json'))['parameters']['pusher_friction']['value']
sys.exit(0 if abs(a - b) < 0.01 * a else 1)"
expect_exit 0 "forecast with one's own polygon" -- "$bin" forecast --model "$tmp/myhex.json" --object-pose 0,0,0 \
  --tip -66,10 --direction 10 --speed 50 --out "$tmp/f0"

# forecast: a straight push and a path file; outputs all together.
expect_exit 0 "forecast a straight push" -- "$bin" forecast --model "$tmp/hex.json" --object-pose 0,0,0 \
  --tip -66,10 --direction 10 --speed 50 --out "$tmp/f1" --samples
for f in forecast.csv forecast.json samples.csv outline.dat forecast.gp; do
  check "forecast wrote $f" test -s "$tmp/f1/$f"
done
expect_in "$tmp/f1/forecast.csv" "t_s,x_mm,y_mm,yaw_deg,radius90_mm,yaw_halfwidth90_deg,tip_x_mm,tip_y_mm" "the CSV header"
expect_in "$tmp/f1/forecast.json" '"format": "pushpred-forecast"' "the forecast JSON says its format"
printf 't_s,x_mm,y_mm\n0,-66,10\n0.5,-41,10\n1.0,-21,20\n' >"$tmp/path.csv"
expect_exit 0 "forecast a path file" -- "$bin" forecast --model "$tmp/hex.json" --object-pose 0,0,0 \
  --path "$tmp/path.csv" --out "$tmp/f2"
expect_in "$tmp/f2/forecast.json" '"kind": "path"' "the plan is the path"

# Bad input: a clear error naming the file or flag, exit 2, nothing written.
expect_exit 2 "a missing object file" -- "$bin" forecast --model "$tmp/none.json" --object-pose 0,0,0 --tip -66,0 \
  --direction 0 --speed 50 --out "$tmp/f3"
expect_in "$tmp/err" "$tmp/none.json: cannot read the object model" "the missing file is named"
expect_absent "$tmp/f3" "no output for a missing object file"
printf '{"format": "pushpred-object-model", "version": 1' >"$tmp/broken.json"
expect_exit 2 "a malformed object file" -- "$bin" forecast --model "$tmp/broken.json" --object-pose 0,0,0 \
  --tip -66,0 --direction 0 --speed 50 --out "$tmp/f4"
expect_in "$tmp/err" "$tmp/broken.json: not valid JSON" "the malformed file is named"
expect_absent "$tmp/f4" "no output for a malformed object file"
sed 's/"shape": "hex"/"shape": "teapot"/' "$tmp/hex.json" >"$tmp/teapot.json"
expect_exit 2 "an unknown shape" -- "$bin" forecast --model "$tmp/teapot.json" --object-pose 0,0,0 --tip -66,0 \
  --direction 0 --speed 50 --out "$tmp/f5"
expect_in "$tmp/err" "$tmp/teapot.json" "the file with the unknown shape is named"
expect_in "$tmp/err" "unknown shape 'teapot'" "the unknown shape is named"
expect_absent "$tmp/f5" "no output for an unknown shape"
expect_exit 2 "a straight push without speed" -- "$bin" forecast --model "$tmp/hex.json" --object-pose 0,0,0 \
  --tip -66,0 --direction 0 --out "$tmp/f6"
expect_in "$tmp/err" "--speed" "the missing speed is named"
expect_exit 2 "a bad pose" -- "$bin" forecast --model "$tmp/hex.json" --object-pose 0,zero,0 --tip -66,0 \
  --direction 0 --speed 50 --out "$tmp/f7"
expect_in "$tmp/err" "--object-pose" "the bad pose is named"
expect_exit 2 "a negative speed" -- "$bin" forecast --model "$tmp/hex.json" --object-pose 0,0,0 --tip -66,0 \
  --direction 0 --speed -5 --out "$tmp/f8"
expect_exit 2 "an unknown flag" -- "$bin" forecast --model "$tmp/hex.json" --object-pose 0,0,0 --wind 3 --out "$tmp/f9"
printf 't_s,x_mm,y_mm\n0,-66,10\n0,-41,10\n' >"$tmp/badpath.csv"
expect_exit 2 "a path whose times do not increase" -- "$bin" forecast --model "$tmp/hex.json" --object-pose 0,0,0 \
  --path "$tmp/badpath.csv" --out "$tmp/f10"
expect_in "$tmp/err" "$tmp/badpath.csv" "the bad path file is named"
printf 't_s,x_mm,y_mm\n# start\n0,-66,10\n0.5,forty,10\n' >"$tmp/wordpath.csv"
expect_exit 2 "a path with a word for a number" -- "$bin" forecast --model "$tmp/hex.json" --object-pose 0,0,0 \
  --path "$tmp/wordpath.csv" --out "$tmp/f11"
expect_in "$tmp/err" "$tmp/wordpath.csv:4: 'forty' is not a number" "the bad path file and line are named"
printf 't_s,x_mm,y_mm\n0,-66,10\n0.5,-41\n' >"$tmp/shortpath.csv"
expect_exit 2 "a path row of two numbers" -- "$bin" forecast --model "$tmp/hex.json" --object-pose 0,0,0 \
  --path "$tmp/shortpath.csv" --out "$tmp/f12"
expect_in "$tmp/err" "$tmp/shortpath.csv:3: expected three numbers t_s,x_mm,y_mm" "the short row's file and line"
expect_exit 2 "a path file that is missing" -- "$bin" forecast --model "$tmp/hex.json" --object-pose 0,0,0 \
  --path "$tmp/nopath.csv" --out "$tmp/f13"
expect_in "$tmp/err" "$tmp/nopath.csv: cannot open a tip path file" "the missing path file is named"
# A plan no push could follow, or an output step of a nanosecond, is refused at once (they ran for ever, or ended in
# std::bad_alloc); a folder as --model is named; a model whose numbers are out of range gives no infinite forecast.
expect_exit 2 "a plan at 1e-6 mm/s" -- timeout 30 "$bin" forecast --model "$tmp/hex.json" --object-pose 0,0,0 \
  --tip -66,10 --direction 10 --speed 1e-6 --out "$tmp/f14"
expect_in "$tmp/err" "--speed, --length: tip plan lasts 5e+07 s, longer than the 600 s a push may last" "the slow plan"
expect_exit 2 "a plan of 1e9 mm" -- timeout 30 "$bin" forecast --model "$tmp/hex.json" --object-pose 0,0,0 \
  --tip -66,10 --direction 10 --speed 50 --length 1e9 --out "$tmp/f15"
expect_in "$tmp/err" "tip plan lasts 2e+07 s" "the long plan"
printf 't_s,x_mm,y_mm\n0,-66,10\n1e6,-41,10\n' >"$tmp/longpath.csv"
expect_exit 2 "a path of 1e6 s" -- timeout 30 "$bin" forecast --model "$tmp/hex.json" --object-pose 0,0,0 \
  --path "$tmp/longpath.csv" --out "$tmp/f16"
expect_in "$tmp/err" "$tmp/longpath.csv: tip path lasts 1e+06 s" "the long path file is named"
printf 't_s,x_mm,y_mm\n0,-66,10\n0.001,1e6,10\n' >"$tmp/fastpath.csv"
expect_exit 2 "a path at 1e6 m/s" -- timeout 30 "$bin" forecast --model "$tmp/hex.json" --object-pose 0,0,0 \
  --path "$tmp/fastpath.csv" --out "$tmp/f17"
expect_in "$tmp/err" "$tmp/fastpath.csv: tip path moves the tip at 1e+06 m/s, faster than the 2 m/s" "the fast path"
# A start or a tip beyond the 10 m within which a recording's positions lie, a yaw beyond a turn, a direction
# beyond a turn (1e300 deg) or not a number: each flag named, nothing written. A yaw of 1e300 deg gave a forecast that
# was not finite, blamed on the object model.
printf 't_s,x_mm,y_mm\n0,-66,10\n100,1e5,10\n' >"$tmp/farpath.csv"
while IFS='|' read -r what args expected; do
  # shellcheck disable=SC2086
  expect_exit 2 "forecast with $what" -- timeout 30 "$bin" forecast --model "$tmp/hex.json" $args --out "$tmp/f30" \
    </dev/null
  expect_in "$tmp/err" "$expected" "forecast with $what: the flag and the problem are named"
  expect_absent "$tmp/f30" "no forecast with $what"
done <<FAR
a yaw of 1e300 deg|--object-pose=0,0,1e300 --tip=-66,10 --direction=10 --speed=50|--object-pose: yaw of 1e+300 deg is beyond a turn (360 deg)
an object 20 m away|--object-pose=20000,0,0 --tip=-66,10 --direction=10 --speed=50|--object-pose: x of 20 m is beyond the plausible 10 m from the robot
a tip 1e297 m away|--object-pose=0,0,0 --tip=-66,1e300 --direction=10 --speed=50|--tip: y of 1e+297 m is beyond the plausible 10 m from the robot
a direction of 1e300 deg|--object-pose=0,0,0 --tip=-66,10 --direction=1e300 --speed=50|--direction: must be a finite number in [-360, 360], got '1e300'
a direction of inf|--object-pose=0,0,0 --tip=-66,10 --direction=inf --speed=50|--direction: must be a finite number in [-360, 360], got 'inf'
a path 100 m long|--object-pose=0,0,0 --path=$tmp/farpath.csv|$tmp/farpath.csv: tip path: row 2: x of 100 m is beyond the plausible 10 m
FAR
# A tip that starts inside the object (a start pose on top of it) is refused, nothing written: it threw the object
# metres away.
expect_exit 2 "a tip inside the object" -- timeout 30 "$bin" forecast --model "$tmp/hex.json" --object-pose 0,0,0 \
  --tip 0,0 --direction 10 --speed 50 --out "$tmp/f31"
expect_in "$tmp/err" "forecast: the tip starts" "the tip inside is named"
expect_in "$tmp/err" "mm inside the object's outline" "the tip inside is named with its depth"
expect_absent "$tmp/f31" "no forecast from a tip inside the object"
expect_exit 2 "an output step of 1e-9 s" -- timeout 30 "$bin" forecast --model "$tmp/hex.json" --object-pose 0,0,0 \
  --tip -66,10 --direction 10 --speed 50 --step 1e-9 --out "$tmp/f18"
expect_in "$tmp/err" "forecast: an output step of 1e-09 s over" "the step is named"
expect_exit 2 "a folder as the object file" -- "$bin" forecast --model "$tmp" --object-pose 0,0,0 --tip -66,10 \
  --direction 10 --speed 50 --out "$tmp/f19"
expect_in "$tmp/err" "$tmp: is a folder, not an object model" "the folder is named"
python3 -c "
import json, sys
d = json.load(open(sys.argv[1]))
big = lambda x: {k: big(v) for k, v in x.items()} if isinstance(x, dict) else [big(v) for v in x] \\
    if isinstance(x, list) else 1e300 if isinstance(x, float) else x
d['regions'] = big(d['regions'])
json.dump(d, open(sys.argv[2], 'w'))" "$tmp/hex.json" "$tmp/huge_regions.json"
expect_exit 2 "a model whose region numbers are all 1e300" -- "$bin" forecast --model "$tmp/huge_regions.json" \
  --object-pose 0,0,0 --tip -66,10 --direction 10 --speed 50 --out "$tmp/f20"
expect_in "$tmp/err" "$tmp/huge_regions.json: the forecast from this object model is not finite" "the model is named"
python3 -c "
import json, sys
d = json.load(open(sys.argv[1]))
d['parameters']['support_friction']['value'] = 1e300
json.dump(d, open(sys.argv[2], 'w'))" "$tmp/hex.json" "$tmp/huge_mu.json"
expect_exit 2 "a model whose support friction is 1e300" -- "$bin" forecast --model "$tmp/huge_mu.json" \
  --object-pose 0,0,0 --tip -66,10 --direction 10 --speed 50 --out "$tmp/f21"
expect_in "$tmp/err" "support_friction of 1e+300 is above 10" "the parameter and its bound are named"
expect_in "$tmp/err" "$tmp/huge_mu.json" "the model is named"
# An object file's own outline, mass and name get learn's checks (reading/physical_bounds.hpp).
for change in "o['outline'] = {'kind': 'circle', 'radius_m': 50}|outline: the outline is 100 m across" \
  "o['mass_kg'] = 1e9|mass: 1e+09 kg is" "o['name'] = 'my box'|forecast object 'my box': a name is letters and digits"; do
  python3 -c "
import json, sys
d = json.load(open(sys.argv[1]))
o = d['object']
${change%%|*}
json.dump(d, open(sys.argv[2], 'w'))" "$tmp/hex.json" "$tmp/absurd_object.json"
  expect_exit 2 "a model with ${change%%|*}" -- "$bin" forecast --model "$tmp/absurd_object.json" --object-pose 0,0,0 \
    --tip -66,10 --direction 10 --speed 50 --out "$tmp/f31"
  expect_in "$tmp/err" "$tmp/absurd_object.json: " "the model is named"
  expect_in "$tmp/err" "${change#*|}" "the problem is named (${change%%|*})"
  expect_absent "$tmp/f31" "no forecast from ${change%%|*}"
done
for d in f6 f7 f8 f9 f10 f11 f12 f13 f14 f15 f16 f17 f18 f19 f20 f21; do
  expect_absent "$tmp/$d" "no output for bad input ($d)"
done

# forecast-study: summary.json with every method's keys, the same output whatever --jobs.
# shellcheck disable=SC2086
expect_exit 0 "a study of six hex pushes" -- "$bin" forecast-study $hex "$frozen" --out "$tmp/s1" --jobs 1
for key in final_pos_mm_mean final_yaw_deg_mean trajectory_pos_mm_mean trajectory_yaw_deg_mean coverage90_pos \
  coverage90_yaw pushes; do
  expect_in "$tmp/s1/summary.json" "\"$key\"" "summary.json holds $key"
done
expect_in "$tmp/s1/summary.json" '"not_moving"' "the not-moving reference"
expect_in "$tmp/s1/summary.json" '"rigid_tip"' "the rigid tip-following reference"
expect_in "$tmp/s1/summary.json" "force sensor frozen" "the excluded push and why"
expect_in "$tmp/s1/tables.md" "from its start only" "the report says what of each push is used"
expect_in "$tmp/s1/summary.json" '"rim_weight_learned": false' "each fold says whether it learned the rim weight"
expect_in "$tmp/s1/summary.json" '"residual_correction": true' "each fold says whether it corrects its central forecast"
expect_in "$tmp/s1/pushes.csv" "fold_rim_weight,fold_rim_weight_learned" "pushes.csv has each fold's rim weight"
expect_in "$tmp/s1/pushes.csv" "yaw_error_tip_stop_deg,yaw_error_final_deg,recorded_turn_after_tip_stop_deg" \
  "pushes.csv says where the yaw error builds up"
expect_in "$tmp/s1/pushes.csv" "measured_pusher_friction" "pushes.csv has the measured rod friction"
# shellcheck disable=SC2086
expect_exit 0 "the same study on two jobs" -- "$bin" forecast-study $hex "$frozen" --out "$tmp/s2" --jobs 2
expect_same_tree "$tmp/s1" "$tmp/s2" "--jobs 1 and 2 write the same study"
expect_exit 2 "a study of one push" -- "$bin" forecast-study "$(echo "$hex" | head -1)" --out "$tmp/s3"
expect_absent "$tmp/s3" "no study of one push"

# limit-surface-study: each push's c from its force and motion, and its relation to the plan.
# shellcheck disable=SC2086
expect_exit 0 "the limit surface study of six hex pushes" -- "$bin" limit-surface-study $hex "$frozen" \
  --out "$tmp/l1" --jobs 1
expect_in "$tmp/l1/pushes.csv" "identified_c_mm,identified_turn_deg,identified_samples" "pushes.csv has each push's c"
expect_in "$tmp/l1/tables.md" "ensemble_identified" "tables.md compares the forecasts"
# shellcheck disable=SC2086
expect_exit 0 "the same limit surface study on two jobs" -- "$bin" limit-surface-study $hex "$frozen" \
  --out "$tmp/l2" --jobs 2
expect_same_tree "$tmp/l1" "$tmp/l2" "--jobs 1 and 2 write the same limit surface study"
expect_exit 2 "a limit surface study of a missing file" -- "$bin" limit-surface-study "$tmp/missing.h5" --out "$tmp/l3"
expect_absent "$tmp/l3" "no limit surface study of a missing file"
if [ "$(grep -c "missing.h5" "$tmp/err")" -eq 1 ]; then passed=$((passed + 1)); else
  failed=$((failed + 1)); echo "FAIL: the missing file is named once"; sed 's/^/  err: /' "$tmp/err"
fi
finish
