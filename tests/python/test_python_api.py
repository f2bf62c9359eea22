"""The module as a Python user meets it: signatures, reprs, type stubs, and the study dict's fields."""
import ast
import inspect
import os
import subprocess
import sys
from pathlib import Path

import pytest

import pushpred

SOURCE = Path(os.environ.get("PUSHPRED_SOURCE_DIR", Path(__file__).resolve().parents[2]))


def public_functions():
    return sorted(n for n in dir(pushpred) if not n.startswith("_") and inspect.isfunction(getattr(pushpred, n)))


def test_inspect_signature_gives_every_functions_parameters_and_defaults():
    assert len(public_functions()) >= 25
    for name in public_functions():
        inspect.signature(getattr(pushpred, name))  # raises ValueError for a bare pybind11 function
    signature = inspect.signature(pushpred.run_prediction_study)
    assert list(signature.parameters)[:3] == ["push", "intervals", "span"]
    assert signature.parameters["intervals"].default == 4
    assert signature.parameters["estimator"].default == "rls"
    load = inspect.signature(pushpred.load_push)
    assert load.parameters["rate_hz"].default == 250.0
    assert load.parameters["path"].default is inspect.Parameter.empty


def test_a_wrapped_function_still_is_the_compiled_one(hex_file):
    # The wrapper passes its arguments on, keywords included, and keeps the docstring.
    push = pushpred.load_push(path=hex_file, rate_hz=125.0)
    assert push.rate_hz == 125.0
    assert "load_push(path" in pushpred.load_push.__doc__
    with pytest.raises(TypeError):
        pushpred.load_push(hex_file, no_such_argument=1)


def test_reprs_say_what_the_object_holds():
    model = pushpred.PredictionModel(0.5, 0.001, beta=[-0.9, -1.0, -0.8], coulomb_force_N=0.2)
    text = repr(model)
    assert text.startswith("PredictionModel(mass_kg=0.5, inertia_kgm2=0.001, beta=[-0.9, -1.0, -0.8]")
    assert "coulomb_force_N=0.2" in text
    # The repr is a constructor call that gives the same model back.
    again = eval(text, {"PredictionModel": pushpred.PredictionModel})
    assert repr(again) == text
    assert repr(pushpred.QFilterObserver(wn_rad_s=200.0)).startswith("QFilterObserver(wn_rad_s=200.0, zeta=")
    assert repr(pushpred.PidForceReconstruction(kp=10.0)).startswith("PidForceReconstruction(kp=10.0, ki=34.6")
    assert repr(pushpred.RecursiveLeastSquares()) == \
        "<pushpred.RecursiveLeastSquares 'rls': not ready (no identification interval fed yet)>"
    assert repr(pushpred.EffectLibrary.standard()).startswith("<pushpred.EffectLibrary of ")


def test_the_study_dict_has_summary_jsons_method_parameters(executable, hex_file, tmp_path):
    from conftest import read_json, run_cli
    study = pushpred.run_prediction_study(pushpred.load_push(hex_file))
    run_cli(executable, "predict", hex_file, "--out", tmp_path / "p", "--jobs", "1")
    summary = read_json(tmp_path / "p" / "summary.json")["files"][0]
    assert len(study["phases"]) == len(summary["phases"])
    for ours, theirs in zip(study["phases"], summary["phases"]):
        assert set(ours["method_parameters"]) == set(theirs.get("method_parameters", {}))
        for method, parameters in theirs.get("method_parameters", {}).items():
            assert set(ours["method_parameters"][method]) == set(parameters)
            for name, q in parameters.items():
                mine = ours["method_parameters"][method][name]
                assert mine["unit"] == q["unit"] and mine["source"] == q["source"]
                assert mine["value"] == pytest.approx(q["value"], rel=1e-9, abs=1e-12)
        assert ours["method_notes"] == theirs.get("method_notes", {})
    assert any(p["method_parameters"] for p in study["phases"]), "no method reported parameters"


def test_the_stubs_are_the_modules():
    stubs = SOURCE / "python" / "pushpred" / "__init__.pyi"
    tree = ast.parse(stubs.read_text())
    declared = {n.name for n in tree.body if isinstance(n, (ast.FunctionDef, ast.ClassDef))}
    public = {n for n in dir(pushpred) if not n.startswith("_") and not inspect.ismodule(getattr(pushpred, n))}
    assert public - declared == set(), "in the module, not in the stubs"
    assert declared - public == set(), "in the stubs, not in the module"
    # Written from this build's module, they are the committed file byte for byte.
    proc = subprocess.run([sys.executable, str(SOURCE / "scripts" / "python-stubs.py"), "--check", str(stubs)],
                          capture_output=True, text=True)
    assert proc.returncode == 0, proc.stdout + proc.stderr
