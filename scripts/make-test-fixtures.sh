#!/usr/bin/env bash
# Writes the recordings in tests/fixtures/rect1_abs/: four simulated pushes of rect1 on a support of friction 0.2,
# in the dataset's HDF5 layout and file names, so that tests can run the program end to end without the real data.
# They are fixed bytes in the repository (a change to the reader or the writer must still read them); rerun this only
# to change what they hold. Usage: scripts/make-test-fixtures.sh [BUILD_DIR=build]
set -eu
build=${1:-build}
here=$(cd "$(dirname "$0")/.." && pwd)
out="$here/tests/fixtures/rect1_abs"
rm -rf "$out"
mkdir -p "$out"
# angle [rad], speed [m/s], seed: through the centre slow and fast, and 20 degrees off the normal either way.
for push in "0.0 0.02 1" "0.349 0.05 2" "-0.349 0.05 3" "0.0 0.08 4"; do
  set -- $push
  "$build/pushpred" simulate --shape rect1 --surface abs --mu 0.2 --speed "$2" --angle "$1" --side 0 --position 0.5 \
    --length 0.05 --seed "$3" --out "$out/"
done
