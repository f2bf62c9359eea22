"""`pushpred plot FILE --out DIR`: one PNG per prediction method and one with all, and data that are the module's
prediction study in mm and degrees."""
import csv
import shutil

import numpy as np
import pytest

import pushpred
from conftest import run_cli


def rows(path):
    with open(path) as f:
        r = list(csv.reader(f))
    return r[0], np.array(r[1:], dtype=float)


def test_plot_writes_every_method_and_the_studys_numbers(executable, hex_file, tmp_path):
    out = tmp_path / "plot"
    proc = run_cli(executable, "plot", hex_file, "--out", out, "--estimator", "batch")
    methods = pushpred.prediction_method_names()
    expected = [f"prediction_{m}" for m in methods] + ["prediction_all"]
    for name in expected:
        assert (out / f"{name}.gp").is_file()
        if shutil.which("gnuplot"):
            png = (out / f"{name}.png").read_bytes()
            assert png[:8] == b"\x89PNG\r\n\x1a\n" and len(png) > 10000
    study = pushpred.run_prediction_study(pushpred.load_push(hex_file), estimator="batch")
    header, data = rows(out / "predictions.csv")
    assert header[:5] == ["phase", "t_s", "measured_x_mm", "measured_y_mm", "measured_theta_deg"]
    for i, phase in enumerate(study["phases"], start=1):
        part = data[data[:, 0] == i]
        np.testing.assert_allclose(part[:, 1], phase["t_s"], rtol=1e-9)
        for m, method in enumerate(methods):
            predicted = phase["predicted"][method]
            np.testing.assert_allclose(part[:, 5 + 3 * m], 1e3 * predicted[:, 0], rtol=1e-8, atol=1e-9)
            np.testing.assert_allclose(part[:, 7 + 3 * m], np.degrees(predicted[:, 2]), rtol=1e-8, atol=1e-9)
        mean = phase["errors"]["dob"]["x_mm_mean"]
        assert mean == pytest.approx(np.mean(np.abs(part[:, 5] - part[:, 2])), rel=1e-6)
    for method in methods:
        assert method in proc.stdout
    _, measured = rows(out / "measured.csv")
    push = pushpred.load_push(hex_file)
    np.testing.assert_allclose(measured[:, 3], np.degrees(push.yaw_rad), rtol=1e-8)


def test_plot_errors_leave_no_output(executable, tmp_path):
    out = tmp_path / "plot"
    proc = run_cli(executable, "plot", tmp_path / "missing.h5", "--out", out, expect=2)
    assert "missing.h5" in proc.stderr
    assert not out.exists()
    run_cli(executable, "plot", "--out", out, expect=2)  # a required argument is missing: a bad argument
