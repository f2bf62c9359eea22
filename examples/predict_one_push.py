"""Predict one push with the paper's method and plot every prediction against the measurement.

    python3 examples/predict_one_push.py [FILE] [--out prediction.png]

FILE defaults to a hexagon push of the real data folder. The push is split into four equal intervals: identify on
the first, predict the second from its first measured pose, add its data, predict the third, and so on."""
import argparse

import matplotlib
matplotlib.use("Agg")  # write files; drop this line to show windows
import matplotlib.pyplot as plt
import numpy as np

import pushpred

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("file", nargs="?", default=pushpred.data_folder() +
                    "/abs/motion_surface=abs_shape=hex_a=0_v=50_i=4.000_s=0.700_t=0.000.h5")
parser.add_argument("--out", default="prediction.png")
args = parser.parse_args()

push = pushpred.load_push(args.file)
study = pushpred.run_prediction_study(push, estimator="rls")

# Positions in mm and yaw in degrees; the library works in metres and radians.
scale = np.array([1e3, 1e3, np.degrees(1.0)])
fig, axes = plt.subplots(3, 1, sharex=True, figsize=(9, 8))
for c, label in enumerate(["x [mm]", "y [mm]", "yaw [deg]"]):
    axes[c].plot(push.t_s, push.pose[:, c] * scale[c], "k", lw=2, label="measured")
    for m, method in enumerate(pushpred.prediction_method_names()):
        for phase in study["phases"]:
            axes[c].plot(phase["t_s"], phase["predicted"][method][:, c] * scale[c], color=f"C{m}",
                         label=method if phase["phase"] == 1 else None)
    for t0, _ in study["intervals_s"]:
        axes[c].axvline(t0, color="gray", ls=":")
    axes[c].set_ylabel(label)
axes[0].legend(loc="upper left", fontsize="small")
axes[-1].set_xlabel("t [s]")
fig.suptitle(push.source.rsplit("/", 1)[-1], fontsize="small")
fig.tight_layout()
fig.savefig(args.out, dpi=100)

for method in pushpred.prediction_method_names():
    e = [phase["errors"][method] for phase in study["phases"]]
    print(f"{method:16s} mean error x {np.mean([x['x_mm_mean'] for x in e]):6.2f} mm, "
          f"y {np.mean([x['y_mm_mean'] for x in e]):6.2f} mm, yaw {np.mean([x['theta_deg_mean'] for x in e]):5.2f} deg")
print("wrote", args.out)
