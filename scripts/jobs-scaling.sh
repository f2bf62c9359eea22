#!/usr/bin/env bash
# How much faster `pushpred predict --jobs 2` is than `--jobs 1`, against what this machine allows
# (docs/performance.md).
#
#   scripts/jobs-scaling.sh [--build DIR] [--data DIR] [--rounds N] [--other-build DIR]
#
# Each round runs, one after the other on the same inputs (default ../shared/data/mcube/abs):
#   j1      predict --jobs 1
#   j2      predict --jobs 2
#   alone   predict --jobs 1 --shard 1/2 (half the inputs, one process)
#   twice   two copies of that same half at the same time, as two processes: the reference. Two processes share
#           nothing but the machine, so twice / alone is what running two things at once costs here (shared
#           caches, memory bandwidth, the hypervisor); the best --jobs 2 can do is about 2 * alone / twice.
# With --other-build DIR, the j1 and j2 runs of that build's pushpred are added to each round (alternating), to
# compare two versions in the same run.
# Prints each round's wall times [s], then the medians and the ratios. Needs GNU time (/usr/bin/time).
set -euo pipefail

build=build
data=../shared/data/mcube/abs
rounds=10
other=
while [ $# -gt 0 ]; do
  case "$1" in
    --build) build=$2; shift 2 ;;
    --data) data=$2; shift 2 ;;
    --rounds) rounds=$2; shift 2 ;;
    --other-build) other=$2; shift 2 ;;
    -h|--help) sed -n 2,16p "$0"; exit 0 ;;
    *) echo "jobs-scaling.sh: unknown argument '$1' (see --help)" >&2; exit 2 ;;
  esac
done
for b in "$build" ${other:+"$other"}; do
  [ -x "$b/pushpred" ] || { echo "jobs-scaling.sh: no pushpred program at '$b/pushpred' (build first)" >&2; exit 2; }
done
[ -e "$data" ] || { echo "jobs-scaling.sh: no data at '$data' (--data DIR)" >&2; exit 2; }
[ -x /usr/bin/time ] || { echo "jobs-scaling.sh: needs GNU time at /usr/bin/time (apt-get install time)" >&2; exit 2; }
[[ "$rounds" =~ ^[1-9][0-9]*$ ]] || { echo "jobs-scaling.sh: --rounds must be a positive whole number" >&2; exit 2; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# Wall time of one run [s]; the exit code does not matter here (an input that fails would make it 1).
wall() {
  rm -rf "$work/out" "$work/out2"
  /usr/bin/time -f %e -o "$work/t" "$@" >/dev/null 2>&1 || true
  tail -1 "$work/t"
}
twice() {
  rm -rf "$work/out" "$work/out2"
  local start end
  start=$(date +%s.%N)
  "$1/pushpred" predict "$data" --out "$work/out" --jobs 1 --shard 1/2 >/dev/null 2>&1 &
  "$1/pushpred" predict "$data" --out "$work/out2" --jobs 1 --shard 1/2 >/dev/null 2>&1 || true
  wait || true
  end=$(date +%s.%N)
  awk -v s="$start" -v e="$end" 'BEGIN { printf "%.3f", e - s }'
}

header="round j1 j2 alone twice"
[ -n "$other" ] && header="$header other_j1 other_j2"
{
echo "$header"
for r in $(seq 1 "$rounds"); do
  line="$r"
  line="$line $(wall "$build/pushpred" predict "$data" --out "$work/out" --jobs 1)"
  line="$line $(wall "$build/pushpred" predict "$data" --out "$work/out" --jobs 2)"
  line="$line $(wall "$build/pushpred" predict "$data" --out "$work/out" --jobs 1 --shard 1/2)"
  line="$line $(twice "$build")"
  if [ -n "$other" ]; then
    line="$line $(wall "$other/pushpred" predict "$data" --out "$work/out" --jobs 1)"
    line="$line $(wall "$other/pushpred" predict "$data" --out "$work/out" --jobs 2)"
  fi
  echo "$line"
done
} | tee "$work/rounds"
python3 - "$work/rounds" <<'EOF'
import statistics, sys
rows = [line.split() for line in open(sys.argv[1])]
names = rows[0][1:] if rows and rows[0][0] == "round" else []
data = [[float(x) for x in r[1:]] for r in rows if r and r[0] != "round"]
if not data:
    sys.exit("jobs-scaling.sh: no round finished")
col = {n: [d[k] for d in data] for k, n in enumerate(names)}
med = {n: statistics.median(v) for n, v in col.items()}
print("median [s]: " + ", ".join(f"{n} {med[n]:.3f}" for n in names))
ratio = [a / b for a, b in zip(col["j1"], col["j2"])]
print(f"j1 / j2 per round: median {statistics.median(ratio):.2f} (range {min(ratio):.2f}-{max(ratio):.2f})")
cost = [t / a for a, t in zip(col["alone"], col["twice"])]
print(f"twice / alone per round: median {statistics.median(cost):.2f}: the best --jobs 2 can do here is about "
      f"{2 / statistics.median(cost):.2f} times --jobs 1")
if "other_j1" in col:
    other = [a / b for a, b in zip(col["other_j1"], col["other_j2"])]
    print(f"other build: j1 / j2 per round: median {statistics.median(other):.2f}; this build's j1 / other's j1: "
          f"median {statistics.median([a / b for a, b in zip(col['j1'], col['other_j1'])]):.2f}")
EOF
