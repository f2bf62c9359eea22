"""Diagnose one object: what the paper's model lacks on its pushes, and the prediction error before and after.

    python3 examples/diagnose_object.py [SHAPE] [--folder DIR] [--limit N]

SHAPE (default hex) selects the real ABS pushes of that object. Alternate pushes fit the effects, the others test
them (held out). The result is the content of `pushpred diagnose`'s diagnosis.json, as a dict."""
import argparse

import pushpred

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("shape", nargs="?", default="hex")
parser.add_argument("--folder", default=pushpred.data_folder() + "/abs")
parser.add_argument("--limit", type=int, default=0, help="only the first N pushes of the object (0: all)")
args = parser.parse_args()

files = [f for f in pushpred.list_recordings(args.folder) if f"shape={args.shape}_" in f]
if args.limit:
    files = files[:args.limit]
pushes, _ = pushpred.run_batch(files, pushpred.load_push)
result = pushpred.diagnose([push for _, push in pushes])

print(result["findings"])
for effect in result["effects"]:
    if effect["selected"]:
        values = ", ".join(f"{name} = {p['value']:.4g} {p['unit']}" for name, p in effect["parameters"].items())
        print(f"  selected {effect['kind']}" + (f": {values}" if values else ""))
print("held-out prediction error (mean position [mm], yaw [deg]):")
references = result["error_references"]
for label, e in [("paper's method (dob)", result["error_before"]), ("corrected", result["error_after"]),
                 ("hold", references["hold"]), ("const_velocity", references["const_velocity"])]:
    print(f"  {label:22s} {e['pos_mm_mean']:6.2f} mm {e['theta_deg_mean']:6.2f} deg")
for failure in result["failures"]:
    print("left out:", failure["source"], failure["reason"])
