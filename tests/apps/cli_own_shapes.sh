#!/usr/bin/env bash
# A researcher's own objects (--shapes FILE, docs/own-objects.md): an own shape gives the same results as the
# dataset's shape written out by hand, every command that reads shapes takes the file, and every bad shape file
# stops the run with exit 2, naming the file and the problem, nothing written.
set -u
bin=$1
data=$2
examples=$3
source "$(dirname "$0")/cli_support.sh"

hex=$(ls "$data"/abs/*shape=hex_a=0_v=50*.h5 | head -2)
disc=$(ls "$data"/abs/*shape=ellip1_a=0_v=20*.h5 | head -1)

# The hexagon and ellip1 written out by hand: a polygon of the hexagon's six vertices and a circle.
python3 - "$tmp/own.json" <<'PY'
import json, math, sys
r = 0.0605
hexagon = [[r * math.cos(math.pi / 3 * k), r * math.sin(math.pi / 3 * k)] for k in range(6)]
json.dump({"format": "pushpred-shapes", "shapes": [
    {"name": "myhex", "mass_kg": 0.9827, "inertia_kgm2": 0.001497, "centroid_m": [0, 0],
     "outline": {"kind": "polygon", "vertices_m": hexagon}},
    {"name": "mydisc", "mass_kg": 0.8937, "inertia_kgm2": 0.001231, "outline": {"kind": "circle", "radius_m": 0.0525}},
    {"name": "hex", "mass_kg": 0.9827, "inertia_kgm2": 0.001497, "outline": {"kind": "polygon", "vertices_m": hexagon}}]},
    open(sys.argv[1], "w"))
with open(sys.argv[1].replace(".json", "_hex.csv"), "w") as f:
    f.write("# the hexagon's vertices\nx_m,y_m\n" + "".join(f"{x!r},{y!r}\n" for x, y in hexagon))
PY
printf 'shape,mass_kg,inertia_kgm2,centroid_x_m,centroid_y_m,geometry,dim1_m,dim2_m,outline_file\nmyhex,0.9827,0.001497,0,0,polygon,,,own_hex.csv\nmydisc,0.8937,0.001231,0,0,circle,0.0525,,\n' >"$tmp/own.csv"

# Same results as the dataset's shapes, byte for byte (the own name aside).
expect_exit 0 "predict with the dataset's hexagon" -- "$bin" predict $hex --shape hex --out "$tmp/hex"
expect_exit 0 "predict with the hexagon as an own polygon (JSON)" -- \
  "$bin" predict $hex --shapes "$tmp/own.json" --shape myhex --out "$tmp/myhex"
expect_exit 0 "predict with the hexagon as an own polygon (CSV)" -- \
  "$bin" predict $hex --shapes "$tmp/own.csv" --shape myhex --out "$tmp/myhex_csv"
expect_same_tree "$tmp/hex" "$tmp/myhex" "an own polygon of the hexagon gives the dataset hexagon's results"
expect_same_tree "$tmp/hex" "$tmp/myhex_csv" "the CSV form gives the same"
expect_exit 0 "an own shape of a dataset name replaces it" -- "$bin" predict $hex --shapes "$tmp/own.json" --out "$tmp/over"
expect_same_tree "$tmp/hex" "$tmp/over" "hex overridden by its own outline gives the same results"
expect_exit 0 "predict with ellip1" -- "$bin" predict "$disc" --out "$tmp/ellip1"
expect_exit 0 "predict with ellip1 as an own circle" -- \
  "$bin" predict "$disc" --shapes "$tmp/own.csv" --shape mydisc --out "$tmp/mydisc"
expect_same_tree "$tmp/ellip1" "$tmp/mydisc" "an own circle of ellip1 gives its results"

# Every command that reads shapes takes --shapes.
for cmd in predict compare diagnose inspect observe plot fit-pid bench simulate learn forecast forecast-study reproduce; do
  expect_exit 0 "$cmd --help" -- "$bin" "$cmd" --help
  expect_in "$tmp/out" "--shapes" "$cmd lists --shapes"
done
expect_exit 0 "inspect an own object" -- "$bin" inspect --shapes "$tmp/own.json" --shape myhex $hex
expect_in "$tmp/out" "myhex" "inspect names the own object"
expect_exit 0 "diagnose with an own object" -- "$bin" diagnose $hex --shapes "$tmp/own.json" --shape myhex --out "$tmp/dg"
expect_in "$tmp/dg/report.md" "myhex" "the diagnosis names the own object"

# learn writes an own object's outline into the object file, which forecast then reads without the shape file.
expect_exit 0 "learn an own object" -- "$bin" learn $hex --shapes "$tmp/own.json" --out "$tmp/object.json"
expect_in "$tmp/object.json" '"kind": "polygon"' "the object file holds the own polygon"
expect_exit 0 "forecast from it without the shape file" -- \
  "$bin" forecast --model "$tmp/object.json" --object-pose 0,0,0 --tip -70,0 --direction 0 --speed 50 --out "$tmp/fc"

# The made-up objects of examples/own_shapes.json simulate, and their recordings predict.
for shape in bracket puck wedge; do
  mkdir -p "$tmp/sim_$shape"
  expect_exit 0 "simulate the example $shape" -- \
    "$bin" simulate --shapes "$examples/own_shapes.json" --shape "$shape" --speed 0.05 --out "$tmp/sim_$shape"
  expect_exit 0 "predict the simulated $shape" -- \
    "$bin" predict "$tmp/sim_$shape" --shapes "$examples/own_shapes.json" --out "$tmp/pred_$shape"
done
expect_exit 2 "a simulated own object without its shape file" -- "$bin" predict "$tmp/sim_bracket" --out "$tmp/no"
expect_in "$tmp/err" "unknown shape 'bracket'" "the unknown shape is named"
expect_absent "$tmp/no" "nothing written without the shape file"

# Every bad shape file: exit 2, the file and the problem named, nothing written.
bad() {  # bad NAME CONTENT EXPECTED-MESSAGE
  printf '%s' "$2" >"$tmp/$1"
  expect_exit 2 "bad shape file $1" -- "$bin" predict $hex --shapes "$tmp/$1" --shape x --out "$tmp/out_$1"
  expect_in "$tmp/err" "$tmp/$1" "$1: the file is named"
  expect_in "$tmp/err" "$3" "$1: the problem is named"
  expect_absent "$tmp/out_$1" "$1: nothing written"
}
header='shape,mass_kg,inertia_kgm2,centroid_x_m,centroid_y_m,geometry,dim1_m,dim2_m'
bad missing_dummy.json '' "not valid JSON"
rm -f "$tmp/missing_dummy.json"
expect_exit 2 "a missing shape file" -- "$bin" predict $hex --shapes "$tmp/nowhere.json" --out "$tmp/nowhere"
expect_in "$tmp/err" "$tmp/nowhere.json: cannot open a shape file" "the missing file is named"
expect_absent "$tmp/nowhere" "nothing written for a missing shape file"
bad short_row.csv "$header"$'\nx,1\n' "expected at least shape,mass_kg,inertia_kgm2"
bad nan.csv "$header"$'\nx,nan,0.001,0,0,circle,0.05,\n' "'nan' is not a number"
bad negative_mass.csv "$header"$'\nx,-1,0.001,0,0,circle,0.05,\n' "mass_kg must be positive"
bad zero_inertia.json '{"shapes": [{"name": "x", "mass_kg": 1, "inertia_kgm2": 0, "outline": {"kind": "circle", "radius_m": 0.05}}]}' "inertia_kgm2 must be positive"
bad crossing.json '{"shapes": [{"name": "x", "mass_kg": 1, "inertia_kgm2": 0.001, "outline": {"kind": "polygon", "vertices_m": [[0, 0], [0.1, 0.1], [0.1, 0], [0, 0.1]]}}]}' "not a simple polygon"
bad two_vertices.json '{"shapes": [{"name": "x", "mass_kg": 1, "inertia_kgm2": 0.001, "outline": {"kind": "polygon", "vertices_m": [[0, 0], [0.1, 0]]}}]}' "at least 3 vertices"
bad clockwise.json '{"shapes": [{"name": "x", "mass_kg": 1, "inertia_kgm2": 0.001, "outline": {"kind": "polygon", "vertices_m": [[0, 0], [0, 0.1], [0.1, 0]]}}]}' "clockwise"
bad twice.json '{"shapes": [{"name": "x", "mass_kg": 1, "inertia_kgm2": 0.001, "outline": {"kind": "circle", "radius_m": 0.05}}, {"name": "x", "mass_kg": 1, "inertia_kgm2": 0.001, "outline": {"kind": "circle", "radius_m": 0.05}}]}' "given twice"
bad bad_name.json '{"shapes": [{"name": "my box", "mass_kg": 1, "inertia_kgm2": 0.001, "outline": {"kind": "circle", "radius_m": 0.05}}]}' "letters and digits"
bad no_outline_file.csv "$header,outline_file"$'\nx,1,0.001,,,polygon,,,nowhere.csv\n' "cannot open an outline file"
expect_exit 2 "an unknown shape name with a shape file" -- \
  "$bin" predict $hex --shapes "$tmp/own.json" --shape teapot --out "$tmp/teapot"
expect_in "$tmp/err" "unknown shape 'teapot'" "the unknown shape is named"
expect_absent "$tmp/teapot" "nothing written for an unknown shape"
finish
