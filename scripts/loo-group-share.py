#!/usr/bin/env python3
"""How much the learned pushes' leave-one-out final errors share within the dataset's groups of pushes.

The dataset pushes each object in groups: several pushes at one contact point (the file name's s) and speed (v),
at consecutive angles (t). For object files written by `pushpred learn`, prints per object and per component of
`loo_final_error` (along and across the plan [mm], yaw [deg]) the share of their variance between the groups
(1 - within-group sum of squares / total sum of squares), and the share chance alone gives (groups - 1) / (pushes -
1). A share well above chance says that a push's neighbours in its group err as it does, which the residual
correction (docs/forecast.md) can learn; near chance, the error is each push's own.

    ./build/pushpred learn ../shared/data/mcube/abs/*shape=hex_* --out hex.json   # and the other objects
    python3 scripts/loo-group-share.py hex.json ellip1.json ellip3.json butter.json
"""
import json
import math
import re
import sys
from collections import defaultdict

COMPONENTS = [("along mm", 1e3), ("across mm", 1e3), ("yaw deg", 180 / math.pi)]


def group_of(name):
    match = re.search(r"v=([\d.]+)_i=([\d.]+)_s=([\d.]+)", name)
    if not match:
        raise SystemExit(f"loo-group-share.py: '{name}' is not a dataset file name (v=..._i=..._s=...)")
    return match.groups()


def main(paths):
    if not paths:
        raise SystemExit(__doc__.strip().splitlines()[-1].strip())
    print("| object | pushes | groups | chance | along mm | across mm | yaw deg |")
    print("| --- | --- | --- | --- | --- | --- | --- |")
    for path in paths:
        with open(path) as f:
            model = json.load(f)
        groups = defaultdict(list)
        for push in model["pushes"]:
            groups[group_of(push["name"])].append(push["loo_final_error"])
        n = sum(len(g) for g in groups.values())
        shares = []
        for j, (_, scale) in enumerate(COMPONENTS):
            values = [e[j] * scale for g in groups.values() for e in g]
            mean = sum(values) / n
            total = sum((v - mean) ** 2 for v in values)
            within = 0.0
            for g in groups.values():
                gm = sum(e[j] * scale for e in g) / len(g)
                within += sum((e[j] * scale - gm) ** 2 for e in g)
            shares.append(1 - within / total if total > 0 else 0.0)
        chance = (len(groups) - 1) / (n - 1) if n > 1 else 0.0
        name = model["object"]["name"]
        print(f"| {name} | {n} | {len(groups)} | {chance:.2f} | " + " | ".join(f"{s:.2f}" for s in shares) + " |")


if __name__ == "__main__":
    main(sys.argv[1:])
