#!/usr/bin/env python3
"""The diagnosis on real pushes that carry a sensor effect injected by this script: data no simulator wrote.

For each object of the real ABS pushes, writes copies of its recordings into a scratch folder (JSON, the MCube
dataset's own form) with one effect added to the force-torque stream, runs `pushpred diagnose` on them, and prints
what was named and the fitted amount against the amount injected on top of what the real data already hold (the
clean copies' fit). The effects a recording can be given exactly, whatever its physics:
- time_offset T [s]: every force stamp later by T (the force stream lags the pose by T more than it did);
- force_offset B [N]: B added to every fx reading (a sensor bias along the robot's x);
- tare: the other way, each push's own mean force before its tip moves removed (force_before_motion), to see what
  the real sensor's per-push offsets do to the diagnosis.
Nothing here was tuned on: the amounts are round numbers chosen before the run (docs/diagnosis.md, "Real pushes with
an injected effect"). The copies are written under the system's temporary folder and removed at the end; nothing
from ../shared is written into the repository.

    PYTHONPATH=build/python python3 scripts/inject-real-effects.py --pushpred build/pushpred \
        --data ../shared/data/mcube/abs [--objects butter,hex] [--jobs 2]
"""
import argparse
import json
import pathlib
import shutil
import subprocess
import sys
import tempfile

import pushpred

CASES = [("none", 0.0), ("time_offset", 0.02), ("time_offset", 0.03), ("force_offset", 0.4), ("force_offset", 1.0),
         ("tare", 0.0)]


def write_copy(source, folder, kind, amount):
    """The recording at `source` as MCube JSON in `folder`, with `kind` injected at `amount`."""
    r = pushpred.read_recording(source)
    offset = force_before_motion(r) if kind == "tare" else None
    doc = {}
    for stream in ("tip_pose", "object_pose", "ft_wrench"):
        columns = list(r[stream].keys())  # t_s first, then the three values
        values = [list(r[stream][c]) for c in columns]
        if stream == "ft_wrench" and kind == "time_offset":
            values[0] = [t + amount for t in values[0]]
        if stream == "ft_wrench" and kind == "force_offset":
            values[1] = [f + amount for f in values[1]]
        if stream == "ft_wrench" and offset:
            values[1] = [f - offset[0][0] for f in values[1]]
            values[2] = [f - offset[0][1] for f in values[2]]
        doc[stream] = [list(row) for row in zip(*values)]
    (folder / (pathlib.Path(source).stem + ".json")).write_text(json.dumps(doc))


def force_before_motion(r):
    """The mean force reading [N] (fx, fy) of recording `r` (pushpred.read_recording) before the tip first moves
    1 mm, less 50 ms, and the readings' standard deviation there; None with fewer than five readings. The rod touches
    nothing then: the true force is zero."""
    tip, ft = r["tip_pose"], r["ft_wrench"]
    moved = None
    for t, x, y in zip(tip["t_s"], tip["x_m"], tip["y_m"]):
        if ((x - tip["x_m"][0]) ** 2 + (y - tip["y_m"][0]) ** 2) ** 0.5 > 1e-3:
            moved = t
            break
    if moved is None:
        return None
    rows = [(fx, fy) for t, fx, fy in zip(ft["t_s"], ft["fx_N"], ft["fy_N"]) if t < moved - 0.05]
    if len(rows) < 5:
        return None
    mean = [sum(r[k] for r in rows) / len(rows) for k in (0, 1)]
    std = (sum((r[0] - mean[0]) ** 2 for r in rows) / (len(rows) - 1)) ** 0.5
    return mean, std


def spread(values):
    m = sum(values) / len(values)
    return m, (sum((v - m) ** 2 for v in values) / (len(values) - 1)) ** 0.5


def effect(report, kind):
    return next(e for e in report["effects"] if e["kind"] == kind)


def effect_summary(report, kind):
    """(named kinds, fitted amount of `kind`, its floor, held-out before / after [mm]) from a diagnosis.json."""
    e = effect(report, kind)
    parameter = e["parameters"]["bias_x" if kind == "force_offset" else "delay"]
    return (list(report["found"]), (parameter["value"], parameter["std"]), e["amount"]["floor"],
            report["error_before"]["pos_mm_mean"], report["error_after"]["pos_mm_mean"])


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--pushpred", required=True, help="the pushpred program")
    parser.add_argument("--data", required=True, help="a folder of real MCube .h5 pushes")
    parser.add_argument("--objects", default="butter,hex,ellip1,ellip3")
    parser.add_argument("--jobs", default="2")
    args = parser.parse_args()
    data = pathlib.Path(args.data)
    scratch = pathlib.Path(tempfile.mkdtemp(prefix="pushpred-inject-"))
    try:
        print("The force sensor before the tip moves (true force zero), per push:\n")
        print("| object | pushes | fx mean, push-to-push std [N] | fy mean, push-to-push std [N] | "
              "within-push std of fx [N] |")
        print("|---|---|---|---|---|")
        for shape in args.objects.split(","):
            stats = [s for s in (force_before_motion(pushpred.read_recording(f))
                                 for f in sorted(data.glob(f"*_shape={shape}_*.h5"))) if s]
            if len(stats) < 2:
                continue
            fx, fy = spread([s[0][0] for s in stats]), spread([s[0][1] for s in stats])
            within = sum(s[1] for s in stats) / len(stats)
            print(f"| {shape} | {len(stats)} | {fx[0]:.2f}, {fx[1]:.2f} | {fy[0]:.2f}, {fy[1]:.2f} | {within:.3f} |")
        print("\nThe diagnosis on copies with an injected effect:\n")
        print("| object | injected | named | fitted (± std) | clean copy's fit | fitted - clean | floor | "
              "held-out pos mm before -> after |")
        print("|---|---|---|---|---|---|---|---|")
        for shape in args.objects.split(","):
            files = sorted(data.glob(f"*_shape={shape}_*.h5"))
            if not files:
                sys.exit(f"inject-real-effects: no pushes of '{shape}' in {data}")
            clean = {}
            for kind, amount in CASES:
                folder = scratch / f"{shape}-{kind}-{amount}"
                folder.mkdir()
                for f in files:
                    write_copy(f, folder, kind, amount)
                out = scratch / f"out-{shape}-{kind}-{amount}"
                run = subprocess.run([args.pushpred, "diagnose", str(folder), "--out", str(out), "--no-plots",
                                      "--jobs", args.jobs], capture_output=True, text=True)
                if run.returncode != 0:
                    print(f"| {shape} | {kind} {amount} | diagnose failed (exit {run.returncode}): "
                          f"{run.stderr.strip().splitlines()[-1]} | | | | | |")
                    continue
                report = json.loads((out / "diagnosis.json").read_text())
                sensor_effects = ("time_offset", "force_offset")
                if kind == "none":
                    clean = {k: effect_summary(report, k)[1] for k in sensor_effects}
                named, fitted, floor, before, after = effect_summary(
                    report, kind if kind in sensor_effects else "time_offset")
                if kind in ("none", "tare"):
                    mu = effect(report, "coulomb_friction")["parameters"]["mu"]
                    label = "nothing" if kind == "none" else "tare (offsets removed)"
                    print(f"| {shape} | {label} | {', '.join(named) or 'nothing'} | base mu {mu['value']:.3f} ± "
                          f"{mu['std']:.2g} | | | | {before:.2f} -> {after:.2f} |")
                    continue
                unit = "s" if kind == "time_offset" else "N"
                base = clean.get(kind)
                print(f"| {shape} | {kind} {amount} {unit} | {', '.join(named) or 'nothing'} | "
                      f"{fitted[0]:.4g} ± {fitted[1]:.2g} | {base[0]:.4g} ± {base[1]:.2g} | "
                      f"{fitted[0] - base[0]:.4g} | {floor:.3g} | {before:.2f} -> {after:.2f} |")
                sys.stdout.flush()
    finally:
        shutil.rmtree(scratch, ignore_errors=True)


if __name__ == "__main__":
    main()
