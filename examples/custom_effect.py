"""Register a physical effect of your own, written in Python, and let the diagnosis test it.

    python3 examples/custom_effect.py [--simulated | FILE...]

The effect here is a drag that grows with the square of the speed, -c m |v| v (and -c I |omega| omega): a law the
library does not ship. With --simulated (the default when no file is given) the pushes are simulated with the
library's viscous drag hidden in them, so one can watch both laws compete for it; otherwise the files given are
diagnosed. The same effect in C++ is examples/cpp/custom_effect.cpp."""
import argparse

import numpy as np

import pushpred


class QuadraticDrag(pushpred.ForceLawEffect):
    def kind(self):
        return "quadratic_drag"

    def description(self):
        return "drag -c (m |v| v, I |omega| omega)"

    def parameters(self):
        return [("c", "1/m")]

    def needs_friction_base(self):
        return True  # tested against a Coulomb friction law, as the library's own friction refinements are

    def unit_force(self, parameter, setting, state, shape):
        v = state["velocity"]  # x', y' [m/s], theta' [rad/s]
        speed = np.hypot(v[0], v[1])
        return [-shape["mass_kg"] * speed * v[0], -shape["mass_kg"] * speed * v[1],
                -shape["inertia_kgm2"] * abs(v[2]) * v[2]]


parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("files", nargs="*")
parser.add_argument("--pushes", type=int, default=12, help="simulated pushes (default 12)")
args = parser.parse_args()

if args.files:
    pushes = [pushpred.load_push(f) for f in args.files]
else:
    rng = np.random.default_rng(1)
    pushes = []
    for k in range(args.pushes):
        scenario = pushpred.paper_case_scenario(1)
        scenario.update(name=f"simulated push {10 + k}", speed_m_s=float(rng.uniform(0.02, 0.15)),
                        contact_side=int(rng.integers(0, 4)), contact_position=float(rng.uniform(0.3, 0.7)),
                        push_angle_rad=float(rng.uniform(-0.25, 0.25)), seed=int(rng.integers(1, 2**31)))
        pushes.append(pushpred.simulate(scenario=scenario, effects={"viscous_friction": 10.0})["push"])

library = pushpred.EffectLibrary.standard()
library.register(QuadraticDrag())
result = pushpred.diagnose(pushes, library)
for effect in result["effects"]:
    if effect["kind"] in ("quadratic_drag", "viscous_friction"):
        c = effect["parameters"]["c"]
        print(f"{effect['kind']:16s} selected {str(effect['selected']):5s} score {effect['score']:10.1f} "
              f"c = {c['value']:.4g} ± {c['std']:.2g} {c['unit']}")
print(result["findings"])
