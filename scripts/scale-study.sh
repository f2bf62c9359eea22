#!/usr/bin/env bash
# Scale study (docs/performance.md): simulate N pushes of random scenarios and time `pushpred predict`
# on them, with its peak memory, for several N and push lengths.
#
#   scripts/scale-study.sh [--build DIR] [--work DIR] [--counts "100 1000 10000"] [--lengths "0.02 0.04 0.08"]
#                          [--length-count 200] [--jobs N] [--seed S]
#
# Scenarios are drawn from the dataset's objects with an outline, speeds and accelerations, sides, contact
# positions and angles (seeded awk, so a given --seed always gives the same pushes). The default pushes are
# 25-50 mm long, as in the validation; the length series holds the count fixed and sets every push's length.
# Prints one line per run: pushes, samples (250 Hz, in the predicted phases), seconds, pushes/s, samples/s, peak
# resident memory [MB].
# Needs GNU time (/usr/bin/time, Debian package `time`). With --work DIR kept, sets already simulated there with
# the same arguments are reused (to time another build on the same pushes).
set -euo pipefail

build=build
work=
counts="100 1000 10000"
lengths="0.02 0.04 0.08"
length_count=200
jobs=$(nproc)
seed=1
while [ $# -gt 0 ]; do
  case "$1" in
    --build) build=$2; shift 2 ;;
    --work) work=$2; shift 2 ;;
    --counts) counts=$2; shift 2 ;;
    --lengths) lengths=$2; shift 2 ;;
    --length-count) length_count=$2; shift 2 ;;
    --jobs) jobs=$2; shift 2 ;;
    --seed) seed=$2; shift 2 ;;
    -h|--help) sed -n 2,13p "$0"; exit 0 ;;
    *) echo "scale-study.sh: unknown argument '$1' (see --help)" >&2; exit 2 ;;
  esac
done
pushpred="$build/pushpred"
[ -x "$pushpred" ] || { echo "scale-study.sh: no pushpred program at '$pushpred' (build first, or --build DIR)" >&2; exit 2; }
[ -x /usr/bin/time ] || { echo "scale-study.sh: needs GNU time at /usr/bin/time (apt-get install time)" >&2; exit 2; }
if [ -z "$work" ]; then work=$(mktemp -d); trap 'rm -rf "$work"' EXIT; fi
mkdir -p "$work"

# One scenario per line: shape speed|- acceleration|- side position angle length seed.
scenarios() {  # count length(empty: random 25-50 mm) seed
  awk -v n="$1" -v len="$2" -v seed="$3" 'BEGIN {
    srand(seed);
    split("rect1 rect2 rect3 ellip1 ellip2 ellip3 hex", shapes, " ");
    split("0.01 0.02 0.05 0.075 0.1 0.15", speeds, " ");
    split("0.2 0.5 1.0 1.5 2.5", accels, " ");
    for (k = 0; k < n; ++k) {
      shape = shapes[int(rand() * 7) + 1];
      if (rand() < 0.3) { v = "-"; a = accels[int(rand() * 5) + 1] } else { v = speeds[int(rand() * 6) + 1]; a = "-" }
      sides = shape ~ /^rect/ ? 4 : (shape == "hex" ? 6 : 1);  # an ellipse outline is one side
      side = int(rand() * sides);
      pos = 0.25 + 0.5 * rand();
      angle = -0.35 + 0.7 * rand();
      l = len == "" ? 0.025 + 0.025 * rand() : len;
      printf "%s %s %s %d %.3f %.3f %.4f %d\n", shape, v, a, side, pos, angle, l, seed * 100000 + k;
    }
  }'
}

simulate_set() {  # dir count length seed
  local dir=$1
  # A set simulated before with the same arguments (--work kept) is reused: the draws are seeded.
  if [ -f "$dir/.arguments" ] && [ "$(cat "$dir/.arguments")" = "$2 $3 $4" ]; then return; fi
  rm -rf "$dir"; mkdir -p "$dir"
  scenarios "$2" "$3" "$4" | while read -r shape v a side pos angle length s; do
    motion=(--speed "$v"); [ "$v" = "-" ] && motion=(--acceleration "$a")
    # Each push in its own folder: random draws may repeat a file name.
    mkdir -p "$dir/$s"
    "$pushpred" simulate --shape "$shape" "${motion[@]}" --side "$side" --position "$pos" --angle "$angle" \
      --length "$length" --seed "$s" --out "$dir/$s/" > /dev/null
  done
  echo "$2 $3 $4" > "$dir/.arguments"
}

run_predict() {  # dir label
  local dir=$1 out="$work/out"
  rm -rf "$out"
  local samples
  /usr/bin/time -f "%e %M" -o "$work/time.txt" "$pushpred" predict "$dir" --out "$out" --jobs "$jobs" > /dev/null
  read -r seconds kb < "$work/time.txt"
  # Samples: the 250 Hz grid samples in the predicted phases (summary.json's phase spans).
  samples=$(python3 -c "import json; d=json.load(open('$out/summary.json')); print(round(250 * sum(p['t1_s'] - p['t0_s'] for f in d['files'] for p in f['phases'])))" 2>/dev/null || echo "?")
  local n
  n=$(find "$dir" -name '*.h5' | wc -l)
  awk -v label="$2" -v n="$n" -v s="$samples" -v t="$seconds" -v kb="$kb" 'BEGIN {
    printf "%-22s pushes %6d  samples %9s  %8.2f s  %8.1f pushes/s  %10s samples/s  peak %7.1f MB\n",
      label, n, s, t, n / t, (s ~ /^[0-9]+$/ ? sprintf("%.0f", s / t) : "?"), kb / 1024 }'
}

echo "pushpred: $("$pushpred" --version)   jobs: $jobs   seed: $seed"
for n in $counts; do
  simulate_set "$work/n$n" "$n" "" "$seed"
  run_predict "$work/n$n" "count $n"
done
for l in $lengths; do
  simulate_set "$work/l$l" "$length_count" "$l" "$seed"
  run_predict "$work/l$l" "length $l m"
done
