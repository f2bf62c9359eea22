"""The diagnosis through the module: the same numbers as `pushpred diagnose`, and an effect written in Python that
the diagnosis finds on simulated pushes whose hidden effect is that very law."""
import numpy as np
import pytest

import pushpred
from conftest import read_json, run_cli


# The diagnosis' slower refinements, off where a test is about the Python path and not about them (whichever of
# them this version of the library has).
FAST = {name: False for name in ("confirm_on_prediction", "fit_base_settings") if name in pushpred.diagnosis_options()}


def hex_files(data_dir, count):
    return [str(p) for p in sorted((data_dir / "abs").glob("*shape=hex_a=0_v=50*.h5"))[:count]]


def test_diagnose_matches_the_cli(executable, data_dir, tmp_path):
    files = hex_files(data_dir, 4)
    run_cli(executable, "diagnose", *files, "--out", tmp_path / "d")
    cli = read_json(tmp_path / "d" / "diagnosis.json")
    mine = pushpred.diagnose([pushpred.load_push(f) for f in files])
    for key in ("error_before", "error_after"):
        for name, value in cli[key].items():
            if isinstance(value, float):
                assert mine[key][name] == pytest.approx(value, rel=1e-9, abs=1e-12), (key, name)
    assert [e["kind"] for e in mine["effects"]] == [e["kind"] for e in cli["effects"]]
    assert [e["selected"] for e in mine["effects"]] == [e["selected"] for e in cli["effects"]]
    assert mine["findings"]
    for phase in mine["traces"]["test_phases"]:
        for method, error in phase["error"].items():
            assert error.shape == (len(phase["t_s"]), 3)


class PythonViscousFriction(pushpred.ForceLawEffect):
    """Drag -c (m v, I omega), the library's viscous_friction written in Python."""

    def kind(self):
        return "python_viscous"

    def description(self):
        return "speed-proportional drag -c (m v, I omega), in Python"

    def parameters(self):
        return [("c", "1/s")]

    def needs_friction_base(self):
        return True

    def unit_force(self, parameter, setting, state, shape):
        v = state["velocity"]
        return [-shape["mass_kg"] * v[0], -shape["mass_kg"] * v[1], -shape["inertia_kgm2"] * v[2]]


def test_an_effect_written_in_python_is_found():
    rng = np.random.default_rng(13)
    amount = 10.0  # [1/s]
    pushes = []
    for k in range(12):
        scenario = pushpred.paper_case_scenario(1)
        scenario.update(name=f"simulated push {10 + k}", speed_m_s=float(rng.uniform(0.02, 0.15)),
                        push_length_m=float(rng.uniform(0.03, 0.05)), contact_side=int(rng.integers(0, 4)),
                        contact_position=float(rng.uniform(0.3, 0.7)), push_angle_rad=float(rng.uniform(-0.25, 0.25)),
                        seed=int(rng.integers(1, 2**31)))
        pushes.append(pushpred.simulate(scenario=scenario, effects={"viscous_friction": amount})["push"])
    library = pushpred.EffectLibrary.standard()
    library.remove("viscous_friction")
    library.register(PythonViscousFriction())
    assert "python_viscous" in library.kinds()
    result = pushpred.diagnose(pushes, library, **FAST)
    found = {e["kind"]: e for e in result["effects"]}["python_viscous"]
    assert found["selected"], result["log"]
    assert found["parameters"]["c"]["unit"] == "1/s"
    assert result["error_after"]["pos_mm_mean"] < result["error_before"]["pos_mm_mean"]
    # The same law in C++ (the library's viscous_friction) gives the same fit: the Python path changes nothing but
    # the language. (How close the fit comes to the hidden amount is the library's own test's business.)
    builtin = pushpred.diagnose(pushes, pushpred.EffectLibrary.standard(), **FAST)
    reference = {e["kind"]: e for e in builtin["effects"]}["viscous_friction"]
    assert reference["selected"]
    for key in ("value", "std"):
        assert found["parameters"]["c"][key] == pytest.approx(reference["parameters"]["c"][key], rel=1e-6)
    assert result["error_after"]["pos_mm_mean"] == pytest.approx(builtin["error_after"]["pos_mm_mean"], rel=1e-6)


def test_library_errors(data_dir):
    library = pushpred.EffectLibrary.standard()
    with pytest.raises(pushpred.InputError):
        library.register(PythonViscousFriction()) or library.register(PythonViscousFriction())
    with pytest.raises(pushpred.InputError):
        library.remove("no_such_effect")
    options = pushpred.diagnosis_options()
    assert options["estimator"] == "rls" and options["bic_threshold"] > 0
    with pytest.raises(pushpred.InputError, match="unknown option 'no_such_option'"):
        pushpred.diagnose([], library, no_such_option=1)
    with pytest.raises(pushpred.InputError):
        pushpred.diagnose([], library)  # no usable push

    class Broken(pushpred.ForceLawEffect):
        def kind(self):
            return "broken"

        def parameters(self):
            return [("c", "1/s")]

        def unit_force(self, parameter, setting, state, shape):
            raise ZeroDivisionError("on purpose")

    bad = pushpred.EffectLibrary()
    bad.register(Broken())
    assert bad.describe()[0]["kind"] == "broken"
    # The Python exception reaches the user with the effect's name: as an InputError, or (where the diagnosis goes on
    # past a failing step) among the result's step failures.
    try:
        result = pushpred.diagnose([pushpred.load_push(f) for f in hex_files(data_dir, 2)], bad)
    except pushpred.InputError as e:
        message = str(e)
    else:
        message = "\n".join(f["what"] for f in result.get("step_failures", []))
    assert "effect 'broken': unit_force raised ZeroDivisionError: on purpose" in message
