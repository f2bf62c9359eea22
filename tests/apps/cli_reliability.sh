#!/usr/bin/env bash
# Inputs and output folders a user or an operator may hand pushpred that must not delete data, lose a batch or run
# away (docs/robustness.md): a recording inside the output folder, a file name at the file system's limit, more jobs
# than cores, upper-case extensions, hard links, a folder owned by another user, and under mpirun a rank that fails.
set -u
bin=$1
data=$2
mpirun=${3:-}
source "$(dirname "$0")/cli_support.sh"

good1=$(abs_push 'shape=hex_a=0_v=50')
good2=$(abs_push 'shape=ellip1_a=0_v=20')
name=$(basename "$good1")
stem=${name%.h5}

# An input inside the output folder: the folder holds a file pushpred did not write, so the run is refused and the
# recording stays.
expect_exit 0 "a first run" -- "$bin" predict "$good1" --out "$tmp/o2" --methods dob,hold
cp "$good1" "$tmp/o2/"
expect_exit 2 "a run into the folder that holds its input" -- "$bin" predict "$tmp/o2/$name" --out "$tmp/o2" \
  --methods dob,hold
expect_in "$tmp/err" "which pushpred did not write there" "the user is told why"
check "the recording inside the output folder is still there" cmp -s "$good1" "$tmp/o2/$name"
expect_exit 2 "the same with a note the user left there" -- "$bin" predict "$good2" --out "$tmp/o2" --methods dob
check "nothing of the folder was touched" test -f "$tmp/o2/summary.json"
rm "$tmp/o2/$name"
expect_exit 0 "the folder is reused once only pushpred's files are in it" -- "$bin" predict "$good2" --out "$tmp/o2" \
  --methods dob,hold
expect_in "$tmp/o2/summary.json" "ellip1" "the new run's output replaced the old"

# A 255-byte file name (the limit of most file systems) in a batch: its outputs' names are shortened, the batch goes
# on, every push is predicted. And an output folder whose name leaves no room for a staging suffix.
mkdir -p "$tmp/long"
long_name="$stem$(printf '0%.0s' $(seq 1 $((255 - ${#stem} - 3)))).h5"
cp "$good1" "$tmp/long/$long_name"
check "the long name has 255 bytes" test "${#long_name}" -eq 255
long_out="$tmp/$(printf 'o%.0s' $(seq 1 230))"
expect_exit 0 "a batch with a 255-byte file name, into a 230-byte folder name" -- "$bin" predict "$tmp/long" "$good2" \
  --out "$long_out" --methods dob,hold
expect_in "$tmp/out" "predicted 2 pushes" "both pushes are predicted"
check "two per-push CSVs" test "$(ls "$long_out/predictions" | wc -l)" -eq 2
check "the staging folder is gone" test -z "$(ls -a "$tmp" | grep '\.staging-')"

# More jobs than cores: capped, said once.
expect_exit 0 "--jobs 2000" -- "$bin" predict "$good1" "$good2" --out "$tmp/jobs" --methods dob,hold --jobs 2000
expect_in "$tmp/err" "note: --jobs 2000 is more than the" "the cap is said"
check "said once" test "$(grep -c 'is more than the' "$tmp/err")" -eq 1

# Upper-case extensions inside a listed folder and given directly; hard links to one file are one push.
mkdir -p "$tmp/upper"
cp "$good1" "$tmp/upper/$stem.H5"
expect_exit 0 "a folder holding a .H5 file" -- "$bin" predict "$tmp/upper" --out "$tmp/up" --methods dob,hold
expect_in "$tmp/out" "predicted 1 pushes" "the .H5 file is listed"
expect_exit 0 "a .H5 file given directly" -- "$bin" predict "$tmp/upper/$stem.H5" --out "$tmp/up2" --methods dob
mkdir -p "$tmp/links/a" "$tmp/links/b"
cp "$good1" "$tmp/links/a/$name"
ln "$tmp/links/a/$name" "$tmp/links/b/$name"
expect_exit 0 "two hard links to one recording" -- "$bin" predict "$tmp/links" --out "$tmp/hl" --methods dob,hold
expect_in "$tmp/out" "predicted 1 pushes" "the push is studied once"
expect_in "$tmp/err" "each push is studied once" "the user is told"

# An output folder owned by another user is refused, touching nothing (root can make one: chown).
if [ "$(id -u)" -eq 0 ] && id nobody >/dev/null 2>&1; then
  expect_exit 0 "a run into a folder" -- "$bin" predict "$good1" --out "$tmp/owned" --methods dob
  chown -R nobody "$tmp/owned"
  expect_exit 2 "the same folder, now another user's" -- "$bin" predict "$good2" --out "$tmp/owned" --methods dob
  expect_in "$tmp/err" "is owned by another user" "the user is told why"
  expect_in "$tmp/owned/summary.json" "hex" "the other user's output is untouched"
  check "no hidden folder is left beside it" test -z "$(ls -a "$tmp" | grep '\.owned\.')"
fi

# Under mpirun, a rank that cannot write its scratch folder stops the whole job at once with exit 2, naming the rank
# and the cause, instead of leaving rank 0 waiting; stale scratch folders of dead ranks are removed by a later run.
if [ -n "$mpirun" ]; then
  export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
  mpi=("$mpirun" --oversubscribe --mca btl self,vader)
  start=$(date +%s)
  expect_exit 2 "mpirun with rank 1's TMPDIR missing" -- timeout 60 "${mpi[@]}" -np 1 "$bin" predict "$good1" "$good2" \
    --out "$tmp/mpi" --methods dob : -np 1 -x TMPDIR="$tmp/no-such-folder" "$bin" predict "$good1" "$good2" \
    --out "$tmp/mpi" --methods dob
  check "the job ended within 30 s" test $(($(date +%s) - start)) -lt 30
  expect_in "$tmp/err" "error on rank 1 of 2" "the failing rank is named"
  expect_absent "$tmp/mpi" "nothing written"
  mkdir -p "$tmp/scratch"
  sleep 0 &
  dead=$!
  wait "$dead"
  mkdir -p "$tmp/scratch/pushpred-predict-rank1-$dead/by-input"
  expect_exit 0 "a run after a rank killed outright" -- env TMPDIR="$tmp/scratch" timeout 60 "${mpi[@]}" -np 2 "$bin" \
    predict "$good1" "$good2" --out "$tmp/mpi2" --methods dob
  expect_absent "$tmp/scratch/pushpred-predict-rank1-$dead" "the dead rank's scratch folder"
fi
finish
