"""The observer and the PID reconstruction: the module against `pushpred observe` on a real push."""
import csv

import numpy as np
import pytest

import pushpred
from conftest import run_cli


def read_csv(path):
    with open(path) as f:
        rows = list(csv.reader(f))
    header, values = rows[0], np.array(rows[1:], dtype=float)
    return {name: values[:, i] for i, name in enumerate(header)}


def close(mine, cli):
    """The CLI prints 10 significant digits."""
    np.testing.assert_allclose(mine, cli, rtol=1e-8, atol=1e-9 * np.max(np.abs(cli)))


def test_observe_matches_the_cli(executable, hex_file, tmp_path):
    run_cli(executable, "observe", hex_file, "--out", tmp_path / "o", "--no-plots")
    cli = read_csv(tmp_path / "o" / "observer.csv")
    obs = pushpred.observe(pushpred.load_push(hex_file))
    close(obs["dob"]["t_s"], cli["t_s"])
    for c, axis in enumerate(("x_N", "y_N", "theta_Nm")):
        close(obs["dob"]["u"][:, c], cli["u_" + axis])
        close(obs["dob"]["d_hat"][:, c], cli["dob_d_" + axis])
        close(obs["pid"]["d_hat"][:, c], cli["pid_d_" + axis])
    for c, axis in enumerate(("x_m_s", "y_m_s", "theta_rad_s")):
        close(obs["dob"]["velocity"][:, c], cli["dob_v_" + axis])
    res = read_csv(tmp_path / "o" / "resimulation.csv")
    close(obs["resimulated_dob"][:, 0], res["dob_x_m"])


def test_estimators_agree_with_observe_and_with_their_exact_discretisation(hex_file):
    push = pushpred.load_push(hex_file)
    obs = pushpred.observe(push)
    dob = pushpred.estimate_disturbance(push, "dob")
    np.testing.assert_array_equal(dob["d_hat"], obs["dob"]["d_hat"])
    pid = pushpred.PidForceReconstruction().estimate(push)
    np.testing.assert_array_equal(pid["d_hat"], obs["pid"]["d_hat"])
    # CVODE against the matrix exponential: the library's own tests hold them together; here the binding of both.
    observer = pushpred.QFilterObserver()
    cvode, exact = observer.estimate(push), observer.estimate_exactly(push)
    scale = np.abs(exact["d_hat"]).max(axis=0)
    assert np.all(np.abs(cvode["d_hat"] - exact["d_hat"]).max(axis=0) < 1e-4 * scale)
    tracking = pushpred.PidForceReconstruction().track(push)
    np.testing.assert_array_equal(tracking["d_hat"], pid["d_hat"])
    assert tracking["simulated_pose"].shape == push.pose.shape
    # The simulated object starts on the measured pose and follows it: its error stays a small part of the travel.
    np.testing.assert_array_equal(tracking["simulated_pose"][0], push.pose[0])
    travel = np.linalg.norm(push.pose[-1, :2] - push.pose[0, :2])
    assert np.abs(tracking["simulated_pose"][:, :2] - push.pose[:, :2]).max() < 0.1 * travel


def test_span_and_options_reach_the_library(hex_file):
    push = pushpred.load_push(hex_file)
    part = pushpred.estimate_disturbance(push, "dob", t_start_s=0.5, t_end_s=1.0)
    assert part["t_s"][0] >= 0.5 and part["t_s"][-1] <= 1.0
    slow = pushpred.QFilterObserver(wn_rad_s=30.0).estimate(push)
    fast = pushpred.QFilterObserver(wn_rad_s=300.0).estimate(push)
    # A slower Q filter smooths d_hat: its sample-to-sample steps are smaller.
    assert np.std(np.diff(slow["d_hat"][:, 0])) < np.std(np.diff(fast["d_hat"][:, 0]))
    with pytest.raises(pushpred.InputError, match="wn"):
        pushpred.QFilterObserver(wn_rad_s=-1.0)
    with pytest.raises(pushpred.InputError):
        pushpred.estimate_disturbance(push, "kalman")
    with pytest.raises(pushpred.InputError):
        pushpred.PidForceReconstruction(kp=-1.0)
