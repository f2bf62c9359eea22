"""Compare the paper's recursive least squares with a batch fit (plain and robust) on a folder of pushes.

    python3 examples/compare_rls_batch.py [FOLDER] [--limit N] [--out comparison.png]

FOLDER defaults to the real ABS pushes. For each push and estimator the paper's study runs end to end; pushes the
study cannot use (a frozen force sensor, no contact) are listed with the reason. Progress goes to stderr."""
import argparse
import collections

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

import pushpred

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("folder", nargs="?", default=pushpred.data_folder() + "/abs")
parser.add_argument("--limit", type=int, default=0, help="only the first N pushes (0: all)")
parser.add_argument("--out", default="comparison.png")
args = parser.parse_args()

files = pushpred.list_recordings(args.folder)
if args.limit:
    files = files[:args.limit]
estimators = ["rls", "batch", "batch_huber"]


def study_all_estimators(path):
    push = pushpred.load_push(path)
    return {name: pushpred.run_prediction_study(push, estimator=name) for name in estimators}


results, failures = pushpred.run_batch(files, study_all_estimators)

# Mean `dob` position error (mean of x and y) per push and estimator [mm].
errors = collections.defaultdict(list)
for _, studies in results:
    for name, study in studies.items():
        e = [ph["errors"]["dob"] for ph in study["phases"]]
        errors[name].append(np.mean([0.5 * (x["x_mm_mean"] + x["y_mm_mean"]) for x in e]))

print(f"{len(results)} pushes studied, {len(failures)} left out")
for name in estimators:
    seconds = sum(s[name]["estimator_seconds"] for _, s in results)
    print(f"{name:12s} mean position error {np.mean(errors[name]):6.2f} mm, median {np.median(errors[name]):6.2f} mm,"
          f" {seconds * 1e3:7.1f} ms in the estimator")
for path, reason in failures:
    print(f"left out: {path.rsplit('/', 1)[-1]}: {reason}")

fig, ax = plt.subplots(figsize=(5, 5))
ax.loglog(errors["rls"], errors["batch"], "o", label="batch")
ax.loglog(errors["rls"], errors["batch_huber"], "x", label="batch_huber")
lo, hi = ax.get_xlim()
ax.plot([lo, hi], [lo, hi], "k:", lw=1)
ax.set_xlabel("RLS: mean position error [mm]")
ax.set_ylabel("batch fit: mean position error [mm]")
ax.legend()
fig.tight_layout()
fig.savefig(args.out, dpi=100)
print("wrote", args.out)
