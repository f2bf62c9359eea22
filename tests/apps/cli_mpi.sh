#!/usr/bin/env bash
# `mpirun -np 2 pushpred predict`, `validate-diagnosis` and `diagnose --per-object`: the ranks split the
# pushes (trials, objects) and rank 0 writes what one process writes,
# byte for byte (diff -r against --jobs 1), with the same stdout, failure list and exit code. Loopback only: the
# shared-memory and self transports of Open MPI on this machine.
set -u
bin=$1
data=$2
mpirun=$3
source "$(dirname "$0")/cli_support.sh"
# Open MPI refuses to start as root unless told; the test machines run as root.
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
# The ranks' temporary folder is one of the test's own: rank 0 merges through a scratch folder there (and each rank
# of diagnose --per-object writes its objects into one), which must be gone after every run.
mkdir -p "$tmp/tmpdir"
mpi=(env TMPDIR="$tmp/tmpdir" "$mpirun" -np 2 --oversubscribe --mca btl self,vader)
# The names of pushpred's folders left in the ranks' temporary folder (Open MPI keeps its own there).
left_in_tmpdir() { find "$tmp/tmpdir" -mindepth 1 -maxdepth 1 -name 'pushpred-*' -printf '%f\n'; }

batch_files

"$bin" predict "${files[@]}" --out "$tmp/plain" --jobs 1 >"$tmp/plain.out" 2>"$tmp/plain.err"
plain_code=$?
timeout 600 "${mpi[@]}" "$bin" predict "${files[@]}" --out "$tmp/mpi" --jobs 1 >"$tmp/mpi.out" 2>"$tmp/mpi.err"
mpi_code=$?
check "mpirun exits as the plain run ($plain_code), got $mpi_code" [ "$mpi_code" -eq "$plain_code" ]
expect_same_tree "$tmp/plain" "$tmp/mpi" "the MPI output differs from the plain run" ||
  sed 's/^/  err: /' "$tmp/mpi.err" | head -20
sed -i "s#$tmp/plain#OUT#g" "$tmp/plain.out"
sed -i "s#$tmp/mpi#OUT#g" "$tmp/mpi.out"
check "rank 0 prints what the plain run prints, once" cmp -s "$tmp/plain.out" "$tmp/mpi.out"
check "the same failures are listed, once" diff <(grep -E '^FAILED' "$tmp/plain.err") <(grep -E '^FAILED' "$tmp/mpi.err")
check "no partial output is left" [ ! -e "$tmp/mpi/partial.json" ]
expect_in "$tmp/plain.out" "predicted 4 pushes" "the plain run predicted the four usable pushes"
check "no scratch folder is left after predict under mpirun: $(left_in_tmpdir)" [ -z "$(left_in_tmpdir)" ]

# Two jobs per rank change nothing.
timeout 600 "${mpi[@]}" "$bin" predict "${files[@]}" --out "$tmp/mpi2" --jobs 2 >/dev/null 2>&1
check "2 ranks x 2 jobs write the same output" diff -r "$tmp/plain" "$tmp/mpi2"

# validate-diagnosis: the ranks split the trials; rank 0 writes what one process writes.
validate=(validate-diagnosis --trials 1 --kinds none,force_offset --min-pushes 4 --max-pushes 4 --quick-base --seed 9000
          --jobs 1)
"$bin" "${validate[@]}" --out "$tmp/vplain" >/dev/null 2>&1
vcode=$?
timeout 600 "${mpi[@]}" "$bin" "${validate[@]}" --out "$tmp/vmpi" >/dev/null 2>&1
check "validate-diagnosis under mpirun exits as the plain run ($vcode)" [ $? -eq "$vcode" ]
check "validate-diagnosis under mpirun writes the same output" diff -r "$tmp/vplain" "$tmp/vmpi"

# diagnose --per-object: the ranks split the objects (every rank reads every file); rank 0 writes what one process
# writes, the plots included (sent as bytes). Three objects, one of which fails, and a missing file.
dfiles=()
for pattern in 'shape=hex_a=0_v=50' 'shape=ellip1_a=0_v=50'; do
  mapfile -t -O "${#dfiles[@]}" dfiles < <(ls "$data"/abs/*"$pattern"*.h5 | head -2)
done
dfiles+=("$(abs_push 'shape=rect1_')" "$tmp/missing.h5")
diagnose=(diagnose --per-object --quick-base --intervals 3 --jobs 1)
"$bin" "${diagnose[@]}" "${dfiles[@]}" --out "$tmp/dplain" >"$tmp/dplain.out" 2>"$tmp/dplain.err"
dcode=$?
timeout 600 "${mpi[@]}" "$bin" "${diagnose[@]}" "${dfiles[@]}" --out "$tmp/dmpi" >"$tmp/dmpi.out" 2>"$tmp/dmpi.err"
code=$?
check "diagnose --per-object under mpirun exits as the plain run ($dcode), got $code" [ "$code" -eq "$dcode" ]
expect_same_tree "$tmp/dplain" "$tmp/dmpi" "the MPI diagnose output differs from the plain run" ||
  sed 's/^/  err: /' "$tmp/dmpi.err" | head -20
sed -i "s#$tmp/dplain#OUT#g" "$tmp/dplain.out"
sed -i "s#$tmp/dmpi#OUT#g" "$tmp/dmpi.out"
check "diagnose: rank 0 prints what the plain run prints, once" cmp -s "$tmp/dplain.out" "$tmp/dmpi.out"
check "diagnose: the same failures are listed, once" \
  diff <(grep -E '^(FAILED|LEFT OUT|[0-9]+ of)' "$tmp/dplain.err") <(grep -E '^(FAILED|LEFT OUT|[0-9]+ of)' "$tmp/dmpi.err")
expect_in "$tmp/dplain.out" "2 of 3 objects diagnosed" "the plain diagnose run diagnosed two objects"
timeout 600 "${mpi[@]}" "$bin" diagnose "${dfiles[0]}" --out "$tmp/bad" >"$tmp/out" 2>"$tmp/err"
check "diagnose without --per-object under mpirun fails" [ $? -ne 0 ]
expect_in "$tmp/err" "only with --per-object" "diagnose without --per-object under mpirun is explained"

# What cannot run under MPI says so, and writes nothing.
timeout 600 "${mpi[@]}" "$bin" predict "${files[0]}" --out "$tmp/bad" --shard 1/2 >"$tmp/out" 2>"$tmp/err"
check "--shard under mpirun fails" [ $? -ne 0 ]
expect_in "$tmp/err" "under mpirun" "--shard under mpirun is explained"
timeout 600 "${mpi[@]}" "$bin" inspect "${files[0]}" >"$tmp/out" 2>"$tmp/err"
check "inspect under mpirun fails" [ $? -ne 0 ]
expect_in "$tmp/err" "does not run under mpirun" "inspect under mpirun is explained"
timeout 600 "${mpi[@]}" "$bin" predict "${files[0]}" "${files[1]}" --out "$tmp/plain/summary.json" >"$tmp/out" 2>"$tmp/err"
check "a bad output folder under mpirun stops every rank with exit 2" [ $? -eq 2 ]
expect_in "$tmp/err" "is not a folder" "the bad output folder is named"
check "no output under a refused mpirun" [ ! -e "$tmp/bad" ]
check "no scratch folder is left after any run under mpirun: $(left_in_tmpdir)" [ -z "$(left_in_tmpdir)" ]
finish
