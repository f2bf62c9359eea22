"""The prediction study and the prediction model: the module against `pushpred predict` on real pushes."""
import numpy as np
import pytest

import pushpred
from conftest import read_json, run_cli


@pytest.mark.parametrize("estimator", ["rls", "batch"])
def test_study_matches_the_cli(executable, hex_file, ellip_file, tmp_path, estimator):
    run_cli(executable, "predict", hex_file, ellip_file, "--out", tmp_path / "p", "--estimator", estimator)
    summary = read_json(tmp_path / "p" / "summary.json")
    for path, cli in zip((hex_file, ellip_file), summary["files"]):
        assert cli["source"] == path
        study = pushpred.run_prediction_study(pushpred.load_push(path), estimator=estimator)
        assert len(study["phases"]) == len(cli["phases"]) == 3
        for mine, theirs in zip(study["phases"], cli["phases"]):
            assert mine["t0_s"] == pytest.approx(theirs["t0_s"], rel=1e-12)
            assert set(mine["errors"]) == set(theirs["methods"])
            for method, errors in theirs["methods"].items():
                for key, value in errors.items():
                    assert mine["errors"][method][key] == pytest.approx(value, rel=1e-9, abs=1e-12), (method, key)
            for c, channel in enumerate(("x", "y", "rotation")):
                assert mine["relation"]["beta"][c] == pytest.approx(theirs["relation"]["channels"][channel]["beta"],
                                                                    rel=1e-9, abs=1e-12)
    mine = pushpred.study_summary([pushpred.load_push(p) for p in (hex_file, ellip_file)], estimator=estimator)
    for method, errors in summary["aggregate"].items():
        for key, value in errors.items():
            assert mine["aggregate"][method][key] == pytest.approx(value, rel=1e-9, abs=1e-12)


def test_the_observers_reading_is_the_clis(executable, hex_file, tmp_path):
    reading = ["--observer-run", "continuous", "--observer-start", "rest", "--observer-output", "point"]
    run_cli(executable, "predict", hex_file, "--out", tmp_path / "p", "--methods", "dob", *reading)
    cli = read_json(tmp_path / "p" / "summary.json")["files"][0]
    study = pushpred.run_prediction_study(pushpred.load_push(hex_file), observer_run="continuous",
                                          observer_start="rest", observer_output="point")
    default = pushpred.run_prediction_study(pushpred.load_push(hex_file))
    for mine, theirs, other in zip(study["phases"], cli["phases"], default["phases"]):
        assert mine["errors"]["dob"]["x_mm_mean"] == pytest.approx(theirs["methods"]["dob"]["x_mm_mean"], rel=1e-9)
        assert mine["relation"]["beta"][0] != pytest.approx(other["relation"]["beta"][0], rel=1e-6)
    with pytest.raises(pushpred.InputError, match="observer output"):
        pushpred.run_prediction_study(pushpred.load_push(hex_file), observer_output="mean")


def test_errors_are_what_the_arrays_say(hex_file):
    study = pushpred.run_prediction_study(pushpred.load_push(hex_file))
    for phase in study["phases"]:
        measured = phase["measured"]
        assert measured.shape == (len(phase["t_s"]), 3)
        for method in pushpred.prediction_method_names():
            predicted = phase["predicted"][method]
            errors = phase["errors"][method]
            assert errors["x_mm_mean"] == pytest.approx(1e3 * np.mean(np.abs(predicted[:, 0] - measured[:, 0])))
            assert errors["theta_deg_mean"] == pytest.approx(
                np.degrees(np.mean(np.abs(predicted[:, 2] - measured[:, 2]))))
        hold = phase["predicted"]["hold"]
        assert np.all(hold == hold[0])


def test_prediction_model_reproduces_the_studys_dob_method(hex_file):
    push = pushpred.load_push(hex_file)
    study = pushpred.run_prediction_study(push)
    phase = study["phases"][0]
    model = pushpred.PredictionModel.from_relation(push, phase["relation"])
    # The study starts every method from the measured pose at the phase start (what `hold` keeps), at rest.
    np.testing.assert_array_equal(phase["predicted"]["hold"][0], push.pose[push.index_at(phase["t0_s"])])
    predicted = pushpred.predict_poses(model, push, phase["t0_s"], phase["t1_s"], output_times_s=phase["t_s"])
    np.testing.assert_allclose(predicted, phase["predicted"]["dob"], rtol=0, atol=1e-12)
    # Newton's law alone under the planned force, with no friction, runs far from the measurement: the relation is
    # what makes the prediction.
    free = pushpred.predict_poses(pushpred.PredictionModel(push.shape["mass_kg"], push.shape["inertia_kgm2"]), push,
                                  phase["t0_s"], phase["t1_s"], output_times_s=phase["t_s"])
    measured = phase["measured"]
    assert np.abs(free - measured)[:, :2].mean() > np.abs(predicted - measured)[:, :2].mean()
    with pytest.raises(pushpred.InputError):
        pushpred.PredictionModel(mass_kg=-1.0, inertia_kgm2=0.01)


def test_the_simple_model_in_closed_form_is_the_studys_and_cvode_regularised_comes_close(hex_file):
    push = pushpred.load_push(hex_file)
    study = pushpred.run_prediction_study(push)
    phase = study["phases"][-1]
    friction = 0.14 * push.shape["mass_kg"] * 9.81
    model = pushpred.PredictionModel(push.shape["mass_kg"], push.shape["inertia_kgm2"], coulomb_force_N=friction,
                                     coulomb_speed_scale_m_s=1e-6)
    closed = pushpred.predict_poses(model, push, phase["t0_s"], phase["t1_s"], output_times_s=phase["t_s"])
    np.testing.assert_allclose(closed, phase["predicted"]["simple"], rtol=0, atol=1e-12)
    cvode = pushpred.predict_poses(model, push, phase["t0_s"], phase["t1_s"], output_times_s=phase["t_s"],
                                   integrator="cvode")
    travel = np.abs(closed[-1, :2] - closed[0, :2]).max()
    assert travel > 0.01  # the planned force exceeds mu m g: the simple model slides away
    assert np.abs(cvode - closed)[:, :2].max() < 1e-6 * max(1.0, travel / 0.01)
    with pytest.raises(pushpred.InputError):
        pushpred.predict_poses(model, push, phase["t0_s"], phase["t1_s"], integrator="rk4")
