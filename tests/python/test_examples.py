"""The examples a researcher copies run as documented, on real pushes (and simulated ones for the custom effect),
and print what the module computes."""
import os
import subprocess
import sys
from pathlib import Path

import pytest

import pushpred

EXAMPLES = Path(os.environ.get("PUSHPRED_SOURCE_DIR", Path(__file__).resolve().parents[2])) / "examples"


def run_example(script, *args, cwd):
    # The example imports the module these tests import, wherever the test runs from.
    env = dict(os.environ, PYTHONPATH=str(Path(pushpred.__file__).resolve().parents[1]))
    proc = subprocess.run([sys.executable, str(EXAMPLES / script), *map(str, args)], capture_output=True, text=True,
                          cwd=cwd, env=env)
    assert proc.returncode == 0, f"{script}: exit {proc.returncode}\n{proc.stderr}"
    return proc


def is_png(path):
    return path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_predict_one_push(hex_file, tmp_path):
    proc = run_example("predict_one_push.py", hex_file, "--out", tmp_path / "p.png", cwd=tmp_path)
    assert is_png(tmp_path / "p.png")
    study = pushpred.run_prediction_study(pushpred.load_push(hex_file))
    dob = sum(ph["errors"]["dob"]["x_mm_mean"] for ph in study["phases"]) / len(study["phases"])
    line = next(l for l in proc.stdout.splitlines() if l.startswith("dob "))
    assert f"mean error x {dob:6.2f} mm" in line


def test_compare_rls_batch(data_dir, tmp_path):
    proc = run_example("compare_rls_batch.py", data_dir / "abs", "--limit", 3, "--out", tmp_path / "c.png",
                       cwd=tmp_path)
    assert "3 pushes studied, 0 left out" in proc.stdout
    for name in ("rls", "batch", "batch_huber"):
        assert any(l.startswith(name + " ") for l in proc.stdout.splitlines())
    assert "[3/3]" in proc.stderr  # progress
    assert is_png(tmp_path / "c.png")


def test_diagnose_object(data_dir, tmp_path):
    proc = run_example("diagnose_object.py", "hex", "--limit", 4, cwd=tmp_path)
    files = [f for f in pushpred.list_recordings(data_dir / "abs") if "shape=hex_" in f][:4]
    result = pushpred.diagnose([pushpred.load_push(f) for f in files])
    assert result["findings"] in proc.stdout
    e = result["error_before"]
    assert f"paper's method (dob)   {e['pos_mm_mean']:6.2f} mm" in proc.stdout


def test_custom_effect_in_python(tmp_path):
    proc = run_example("custom_effect.py", "--pushes", 8, cwd=tmp_path)
    assert "quadratic_drag" in proc.stdout and "viscous_friction" in proc.stdout


def test_custom_effect_in_cpp(data_dir):
    folder = os.environ.get("PUSHPRED_EXAMPLES_BINARY_DIR")
    if not folder:
        pytest.skip("the C++ examples are not built (PUSHPRED_BUILD_EXAMPLES=OFF)")
    files = [f for f in pushpred.list_recordings(data_dir / "abs") if "shape=hex_" in f][:4]
    proc = subprocess.run([os.path.join(folder, "custom_effect"), *files], capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr
    assert "quadratic_drag: " in proc.stdout
    bad = subprocess.run([os.path.join(folder, "custom_effect")], capture_output=True, text=True)
    assert bad.returncode == 2 and "usage" in bad.stderr
