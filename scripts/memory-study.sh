#!/bin/bash
# Peak memory of `pushpred predict` over one set of pushes, run every way it can be split (docs/performance.md,
# "Scale and memory"): a plain run, two shards and their merge, and mpirun -np 2 (each rank).
# Prints one line per run (wall seconds, peak resident memory by GNU time) and checks that the merged and the MPI
# outputs are the plain run's, byte for byte.
#
#   scripts/memory-study.sh --set DIR [--build DIR] [--jobs N] [--work DIR]
#
# DIR is a folder of pushes, e.g. one that scripts/scale-study.sh --work W simulated (W/n3000). Needs GNU time
# (/usr/bin/time, Debian package `time`); the MPI run is skipped when mpirun is not found. Exit 1 when an output
# differs.
set -euo pipefail

build=build
set_dir=
jobs=2
work=
while [ $# -gt 0 ]; do
  case "$1" in
    --build) build=$2; shift 2 ;;
    --set) set_dir=$2; shift 2 ;;
    --jobs) jobs=$2; shift 2 ;;
    --work) work=$2; shift 2 ;;
    *) echo "memory-study.sh: unknown argument '$1'" >&2; exit 2 ;;
  esac
done
[ -n "$set_dir" ] || { echo "memory-study.sh: give --set DIR (a folder of pushes)" >&2; exit 2; }
[ -d "$set_dir" ] || { echo "memory-study.sh: no folder '$set_dir'" >&2; exit 2; }
pushpred="$build/pushpred"
[ -x "$pushpred" ] || { echo "memory-study.sh: no pushpred program at '$pushpred' (build first, or --build DIR)" >&2; exit 2; }
[ -x /usr/bin/time ] || { echo "memory-study.sh: needs GNU time (apt-get install time)" >&2; exit 2; }
if [ -z "$work" ]; then work=$(mktemp -d); trap 'rm -rf "$work"' EXIT; fi
mkdir -p "$work"

# pushpred exits 1 when some inputs fail; only the memory and the outputs matter here.
measure() {  # LABEL COMMAND...
  local label=$1; shift
  /usr/bin/time -f "%e s %M KB" -o "$work/time.txt" "$@" >/dev/null 2>"$work/stderr.txt" || true
  echo "$label: $(cat "$work/time.txt" | tail -1)"
}

rm -rf "$work/plain" "$work/s1" "$work/s2" "$work/merged" "$work/mpi"
measure "predict --jobs $jobs" "$pushpred" predict "$set_dir" --out "$work/plain" --jobs "$jobs"
measure "predict --shard 1/2 --jobs $jobs" "$pushpred" predict "$set_dir" --out "$work/s1" --shard 1/2 --jobs "$jobs"
measure "predict --shard 2/2 --jobs $jobs" "$pushpred" predict "$set_dir" --out "$work/s2" --shard 2/2 --jobs "$jobs"
measure "merge of the two" "$pushpred" merge --out "$work/merged" "$work/s1" "$work/s2"
status=0
diff -r "$work/plain" "$work/merged" >/dev/null || { echo "the merged output differs from the plain run's"; status=1; }

if command -v mpirun >/dev/null; then
  # Each rank under its own GNU time, which writes to a file named by the rank.
  cat > "$work/rank_time.sh" <<EOF
#!/bin/sh
exec /usr/bin/time -f "%M KB" -o "$work/rank\${OMPI_COMM_WORLD_RANK}.txt" "\$@"
EOF
  chmod +x "$work/rank_time.sh"
  OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 mpirun -np 2 --oversubscribe --mca btl self,vader \
    "$work/rank_time.sh" "$pushpred" predict "$set_dir" --out "$work/mpi" --jobs 1 >/dev/null 2>&1 || true
  echo "mpirun -np 2 predict --jobs 1: rank 0 $(cat "$work/rank0.txt"), rank 1 $(cat "$work/rank1.txt")"
  diff -r "$work/plain" "$work/mpi" >/dev/null || { echo "the MPI output differs from the plain run's"; status=1; }
fi
[ $status -eq 0 ] && echo "merged and MPI outputs: identical to the plain run's"
exit $status
