#!/usr/bin/env python3
"""Where the whole-push forecast's yaw error comes from, from a forecast study's pushes.csv (docs/forecast.md,
"Where the yaw error comes from").

    ./build/pushpred forecast-study ../shared/data/mcube/abs --out results/forecast-study --jobs 1
    python3 scripts/forecast-yaw-error.py results/forecast-study/pushes.csv

Prints, for the forecast and the own fit (oracle): how the signed yaw error grows over the plan (a quarter, a half,
three quarters of its time, its end where the tip stops, and the final pose after the slide to rest), per object;
the final yaw error by the file name's speed and push angle; and the rod's friction the force sensor measured where
the contact slides against the pushes' fitted rod friction. Standard library only.
"""
import collections
import csv
import math
import re
import statistics
import sys

STAGES = ["yaw_error_quarter_deg", "yaw_error_half_deg", "yaw_error_three_quarters_deg", "yaw_error_tip_stop_deg",
          "yaw_error_final_deg"]
STAGE_NAMES = ["1/4", "1/2", "3/4", "tip stops", "final"]


def name_parameters(push):
    m = re.search(r"_v=([-0-9.]+)_i=([0-9.]+)_s=([0-9.]+)_t=([-0-9.]+)", push)
    if not m:
        return None
    return {"speed": float(m.group(1)), "side": int(float(m.group(2))), "position": float(m.group(3)),
            "angle_deg": math.degrees(float(m.group(4)))}


def mean(values):
    values = list(values)
    return sum(values) / len(values) if values else float("nan")


def quantile(values, q):
    values = sorted(values)
    if not values:
        return float("nan")
    x = q * (len(values) - 1)
    lo = int(math.floor(x))
    hi = min(lo + 1, len(values) - 1)
    return values[lo] + (x - lo) * (values[hi] - values[lo])


def main(path):
    rows = list(csv.DictReader(open(path)))
    missing = [c for c in STAGES + ["recorded_turn_after_tip_stop_deg", "measured_pusher_friction"] if c not in rows[0]]
    if missing:
        sys.exit(f"{path}: no column {', '.join(missing)} (a forecast-study output of an older pushpred?)")
    by_method = collections.defaultdict(dict)
    for r in rows:
        by_method[r["method"]][r["push"]] = r
    forecast, oracle = by_method["forecast"], by_method["oracle_own_fit"]
    pushes = sorted(forecast)
    objects = sorted({forecast[p]["object"] for p in pushes})

    print(f"# Where the forecast's yaw error comes from ({len(pushes)} pushes, {path})\n")
    print("## How the yaw error grows over the plan (degrees)\n")
    print("Mean |yaw error| at each stage, and its signed part: the mean of the error times the sign of the push's "
          "final error (equal to the mean |error| at the end; a share of it at a stage is the share of the final "
          "error already there).\n")
    print("| pushes | method | " + " | ".join(STAGE_NAMES) + " | signed share at 1/4, 1/2, 3/4 |")
    print("| --- | --- | " + " | ".join("---" for _ in STAGE_NAMES) + " | --- |")
    for group in ["all"] + objects:
        members = [p for p in pushes if group == "all" or forecast[p]["object"] == group]
        for label, table in (("forecast", forecast), ("own fit", oracle)):
            absolute = [mean(abs(float(table[p][s])) for p in members) for s in STAGES]
            signed = [mean(float(table[p][s]) * math.copysign(1, float(table[p]["yaw_error_final_deg"]))
                           for p in members) for s in STAGES]
            share = ", ".join(f"{x / signed[-1]:.2f}" for x in signed[:3]) if signed[-1] > 0 else ""
            print(f"| {group} ({len(members)}) | {label} | " + " | ".join(f"{x:.2f}" for x in absolute) +
                  f" | {share if label == 'forecast' else ''} |")

    slide_change = [abs(float(forecast[p]["yaw_error_final_deg"]) - float(forecast[p]["yaw_error_tip_stop_deg"]))
                    for p in pushes]
    recorded_slide = [abs(float(forecast[p]["recorded_turn_after_tip_stop_deg"])) for p in pushes]
    print(f"\nAfter the tip stops: the recorded objects turn {mean(recorded_slide):.2f} degrees on average "
          f"(at most {max(recorded_slide):.2f}); the forecast's yaw error changes by {mean(slide_change):.2f} on "
          f"average (at most {max(slide_change):.2f}).\n")

    print("## Final yaw error by the file name's speed and push angle (degrees)\n")
    print("| speed mm/s | pushes | objects | forecast | own fit | recorded turn |")
    print("| --- | --- | --- | --- | --- | --- |")
    by_speed = collections.defaultdict(list)
    for p in pushes:
        by_speed[name_parameters(p)["speed"]].append(p)
    for v in sorted(by_speed):
        members = by_speed[v]
        print(f"| {v:g} | {len(members)} | {', '.join(sorted({forecast[p]['object'] for p in members}))} | "
              f"{mean(float(forecast[p]['final_yaw_deg']) for p in members):.2f} | "
              f"{mean(float(oracle[p]['final_yaw_deg']) for p in members):.2f} | "
              f"{mean(float(forecast[p]['recorded_turn_deg']) for p in members):.2f} |")
    print("\n| push angle, deg | pushes | forecast | own fit | recorded turn |")
    print("| --- | --- | --- | --- | --- |")
    by_angle = collections.defaultdict(list)
    for p in pushes:
        by_angle[int(round(abs(name_parameters(p)["angle_deg"]) / 20) * 20)].append(p)
    for a in sorted(by_angle):
        members = by_angle[a]
        print(f"| {a} | {len(members)} | {mean(float(forecast[p]['final_yaw_deg']) for p in members):.2f} | "
              f"{mean(float(oracle[p]['final_yaw_deg']) for p in members):.2f} | "
              f"{mean(float(forecast[p]['recorded_turn_deg']) for p in members):.2f} |")

    print("\n## The rod's friction: measured by the force sensor where the contact slides, and fitted\n")
    print("| object | pushes measured | measured median (quartiles) | fitted mu_p median (min-max), same pushes | "
          "final yaw error, fitted mu_p within 1.5x of the measured / beyond |")
    print("| --- | --- | --- | --- | --- |")
    for group in ["all"] + objects:
        members = [p for p in pushes if (group == "all" or forecast[p]["object"] == group) and
                   forecast[p]["measured_pusher_friction"] != ""]
        measured = [float(forecast[p]["measured_pusher_friction"]) for p in members]
        fitted = [float(forecast[p]["own_pusher_friction"]) for p in members]
        near = [float(forecast[p]["final_yaw_deg"]) for p, m, f in zip(members, measured, fitted)
                if max(m / f, f / m) <= 1.5]
        far = [float(forecast[p]["final_yaw_deg"]) for p, m, f in zip(members, measured, fitted)
               if max(m / f, f / m) > 1.5]
        print(f"| {group} | {len(members)} | {statistics.median(measured):.3f} ({quantile(measured, 0.25):.3f}-"
              f"{quantile(measured, 0.75):.3f}) | {statistics.median(fitted):.3f} ({min(fitted):.3f}-"
              f"{max(fitted):.3f}) | {mean(near):.2f} ({len(near)}) / {mean(far):.2f} ({len(far)}) |")
    logs_m = [math.log(float(forecast[p]["measured_pusher_friction"])) for p in pushes
              if forecast[p]["measured_pusher_friction"] != ""]
    logs_f = [math.log(float(forecast[p]["own_pusher_friction"])) for p in pushes
              if forecast[p]["measured_pusher_friction"] != ""]
    print(f"\nSpread over the measured pushes (sd of the logarithm): measured {statistics.pstdev(logs_m):.2f}, "
          f"fitted {statistics.pstdev(logs_f):.2f}.")


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit("usage: forecast-yaw-error.py STUDY_DIR/pushes.csv")
    main(sys.argv[1])
