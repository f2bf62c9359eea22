#!/usr/bin/env python3
"""Prints each benchmark's time as a multiple of a reference benchmark from the same run.

Usage: BENCH --benchmark_format=json | python3 bench/ratios.py REFERENCE
REFERENCE is matched against the end of the benchmark names (e.g. "/rls"); the first match is the reference.
With --benchmark_repetitions=N, only the medians are compared.
"""
import json
import sys


def main() -> int:
    if len(sys.argv) != 2:
        print(__doc__.strip(), file=sys.stderr)
        return 2
    suffix = sys.argv[1]
    runs = json.load(sys.stdin)["benchmarks"]
    medians = [b for b in runs if b.get("run_type") == "aggregate" and b.get("aggregate_name") == "median"]
    runs = medians or [b for b in runs if b.get("run_type", "iteration") == "iteration"]
    name = lambda b: b.get("run_name", b["name"])
    reference = next((b for b in runs if name(b).endswith(suffix)), None)
    if reference is None:
        print(f"no benchmark name ends with '{suffix}'", file=sys.stderr)
        return 2
    for b in runs:
        print(f"{name(b):<50} {b['real_time'] / reference['real_time']:10.1f} x {name(reference)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
