"""The simulator: the module against `pushpred simulate`, and hidden effects reaching the recording."""
import numpy as np
import pytest

import pushpred
from conftest import run_cli


def test_paper_case_matches_the_cli(executable, tmp_path):
    out = tmp_path / "case2.h5"
    run_cli(executable, "simulate", "--case", 2, "--out", out)
    from_file = pushpred.load_push(str(out), shape="rect2")
    sim = pushpred.simulate(paper_case=2)
    np.testing.assert_array_equal(sim["push"].pose, from_file.pose)
    np.testing.assert_array_equal(sim["push"].force_N, from_file.force_N)
    assert sim["scenario"] == pushpred.paper_case_scenario(2)
    written = pushpred.simulate(paper_case=2, out=str(tmp_path / "again.h5"))
    assert written["path"] == str(tmp_path / "again.h5")
    np.testing.assert_array_equal(pushpred.load_push(written["path"], shape="rect2").pose, from_file.pose)


def test_truth_and_recording_agree():
    sim = pushpred.simulate(paper_case=1)
    truth, push = sim["truth"], sim["push"]
    # The recording's object travel is the truth's, to the pose sensor's noise (sub-millimetre).
    travel_truth = np.linalg.norm(truth["tracked_pose"][-1, :2] - truth["tracked_pose"][0, :2])
    travel_recorded = np.linalg.norm(push.pose[-1, :2] - push.pose[0, :2])
    assert travel_truth > 0.02
    assert travel_recorded == pytest.approx(travel_truth, abs=1e-3)
    assert truth["rod_peak_speed_m_s"] == pytest.approx(0.01, rel=0.02)


def test_hidden_effect_reaches_the_recording_and_scenarios_round_trip():
    clean = pushpred.simulate(paper_case=1, seed=5)["push"]
    biased = pushpred.simulate(paper_case=1, seed=5, effects={"force_offset": 0.5})["push"]
    rest = clean.t_s < 0.1  # before the rod moves (rest_before_s = 0.18 s)
    # The sensor reads the reaction on the pusher; f_C is its negative, so a bias of +0.5 N shows as -0.5 N (up to
    # the rotation by the tip's yaw into {R}, below 1e-3 rad).
    np.testing.assert_allclose(biased.force_N[rest].mean(axis=0) - clean.force_N[rest].mean(axis=0), [-0.5, -0.5],
                               atol=1e-3)
    scenario = pushpred.paper_case_scenario(3)
    scenario["seed"] = 7
    a = pushpred.simulate(scenario=scenario)["push"]
    b = pushpred.simulate(paper_case=3, seed=7)["push"]
    np.testing.assert_array_equal(a.pose, b.pose)
    names = [e["name"] for e in pushpred.effect_catalogue()]
    assert "viscous_friction" in names and "force_offset" in names
    with pytest.raises(pushpred.InputError, match="unknown effect"):
        pushpred.simulate(paper_case=1, effects={"gravity_waves": 1.0})
    with pytest.raises(pushpred.InputError):
        pushpred.simulate(paper_case=7)
    with pytest.raises(pushpred.InputError, match="scenario"):
        pushpred.simulate(scenario={"shape": "rect2", "no_such_key": 1})
