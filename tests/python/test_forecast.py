"""The whole-push forecast from Python: numpy in, numpy out, the same numbers as `pushpred learn` and `forecast`."""
import json

import numpy as np
import pytest

import pushpred
from conftest import run_cli


# One plan, as the CLI takes it and as the Python forecast takes it: the tip at (-66, 10) mm pushing 10 degrees off
# the x axis at 50 mm/s, the object at rest at the origin.
_PLAN_DIRECTION_RAD = np.deg2rad(10.0)
PLAN = dict(tip=np.array([-0.066, 0.010]),
            direction=np.array([np.cos(_PLAN_DIRECTION_RAD), np.sin(_PLAN_DIRECTION_RAD)]), speed_m_s=0.05)


def cli_forecast(executable, model_file, out):
    """`pushpred forecast` of PLAN with the object file `model_file`: its forecast.csv."""
    run_cli(executable, "forecast", "--model", model_file, "--object-pose", "0,0,0", "--tip", "-66,10",
            "--direction", "10", "--speed", "50", "--out", out)
    return np.genfromtxt(out / "forecast.csv", delimiter=",", names=True)


@pytest.fixture(scope="module")
def hex_files(data_dir):
    return [str(p) for p in sorted((data_dir / "abs").glob("*shape=hex_*.h5"))[:6]]


@pytest.fixture(scope="module")
def model(hex_files):
    return pushpred.learn_object_model(hex_files, jobs=2)


def test_learned_model_matches_the_cli(executable, hex_files, model, tmp_path):
    run_cli(executable, "learn", *hex_files, "--out", tmp_path / "hex.json", "--jobs", 1)
    from_cli = json.loads((tmp_path / "hex.json").read_text())
    assert model.to_dict()["parameters"] == from_cli["parameters"]
    assert model.name == "hex" and model.surface == "abs"
    again = pushpred.read_object_model(str(tmp_path / "hex.json"))
    assert again.parameters == model.parameters
    # The centre of friction (learned over the six pushes, or the centroid kept), as the file keeps it.
    assert model.centre_of_friction_pushes == from_cli["object"]["centre_of_friction"]["learned_from_pushes"]
    np.testing.assert_allclose(model.centre_of_friction_m, from_cli["object"]["centre_of_friction_m"], atol=1e-12)
    np.testing.assert_allclose(again.centre_of_friction_standard_error_m,
                               from_cli["object"]["centre_of_friction"]["standard_error_m"], atol=1e-12)


def test_forecast_matches_the_cli_and_its_regions_grow(executable, model, tmp_path):
    (tmp_path / "hex.json").write_text(json.dumps(model.to_dict()))
    cli = cli_forecast(executable, tmp_path / "hex.json", tmp_path / "f")
    f = model.forecast(np.zeros(3), **PLAN)
    np.testing.assert_allclose(f["t_s"], cli["t_s"], atol=1e-9)
    np.testing.assert_allclose(1e3 * f["pose"][:, 0], cli["x_mm"], atol=1e-6)
    np.testing.assert_allclose(1e3 * f["radius90_m"], cli["radius90_mm"], atol=1e-6)
    assert f["pose"].shape == (len(f["t_s"]), 3)
    # The object moves forward, and the region at rest is wider than at the start.
    assert f["pose"][-1, 0] > 0.02
    assert f["radius90_m"][-1] > f["radius90_m"][0]


def test_batch_forecasts_many_plans_as_single_forecasts_do(model):
    angles = np.deg2rad(np.array([-20.0, 0.0, 20.0]))
    tips = np.array([[-0.066, 0.0]] * 3)
    directions = np.stack([np.cos(angles), np.sin(angles)], axis=1)
    batch = model.forecast_batch(np.zeros(3), tips, directions, np.full(3, 0.05))
    assert batch["final_pose"].shape == (3, 3)
    for i in range(3):
        single = model.forecast(np.zeros(3), tip=tips[i], direction=directions[i], speed_m_s=0.05,
                                times_s=np.array([1e6]))
        np.testing.assert_allclose(batch["final_pose"][i], single["pose"][0], atol=1e-12)
    # The mechanics, without the residual correction (which shifts the forecast by what the learned pushes erred,
    # symmetric or not): pushing +x through the hexagon's vertex and its centroid turns it the way its learned centre
    # of friction says (counter-clockwise when the centre lies above the line of pushing); with the centre at the
    # centroid, not at all, and the angled pushes turn opposite ways.
    d = model.to_dict()
    d["residual_correction"]["applied"] = False
    plain = pushpred.object_model_from_dict(d).forecast_batch(np.zeros(3), tips, directions, np.full(3, 0.05))
    cof_y = model.centre_of_friction_m[1]
    assert model.centre_of_friction_pushes == 0 or np.sign(plain["final_pose"][1, 2]) == np.sign(cof_y)
    d["object"]["centre_of_friction_m"] = [0.0, 0.0]
    centred = pushpred.object_model_from_dict(d).forecast_batch(np.zeros(3), tips, directions, np.full(3, 0.05))
    assert abs(centred["final_pose"][1, 2]) < 1e-9
    assert np.sign(centred["final_pose"][0, 2]) == -np.sign(centred["final_pose"][2, 2])


def test_bad_input_is_a_value_error_naming_it(model):
    with pytest.raises(pushpred.InputError, match="object_pose"):
        model.forecast(np.zeros(2), tip=np.zeros(2), direction=np.array([1.0, 0.0]), speed_m_s=0.05)
    with pytest.raises(pushpred.InputError, match="speed"):
        model.forecast(np.zeros(3), tip=np.zeros(2), direction=np.array([1.0, 0.0]), speed_m_s=-1.0)
    with pytest.raises(pushpred.InputError, match="teapot"):
        d = model.to_dict()
        d["object"]["outline"]["shape"] = "teapot"
        pushpred.object_model_from_dict(d)
    # A model dict holding NaN names the argument (it was a RuntimeError quoting a JSON parse error); a plan slower or
    # longer than any push, or an output step of a nanosecond, is refused instead of running for ever.
    d = model.to_dict()
    d["similarity_bandwidth"] = float("nan")
    with pytest.raises(pushpred.InputError, match="object model: holds NaN or an infinity"):
        pushpred.object_model_from_dict(d)
    with pytest.raises(pushpred.InputError, match="tip plan lasts 5e\\+07 s, longer than the 600 s"):
        model.forecast(np.zeros(3), tip=PLAN["tip"], direction=PLAN["direction"], speed_m_s=1e-9)
    with pytest.raises(pushpred.InputError, match="jobs must be at least 1, got 0"):
        pushpred.learn_object_model(["unused.h5"], jobs=0)
    with pytest.raises(pushpred.InputError, match="tip path lasts 1e\\+06 s, longer than the 600 s"):
        model.forecast(np.zeros(3), path_times_s=np.array([0.0, 1e6]),
                       path_points_m=np.array([[-0.066, 0.010], [-0.016, 0.010]]))


def test_the_pressures_rim_weight_is_learned_as_the_cli_learns_it(executable, hex_files, tmp_path):
    files = hex_files[:4]
    learned = pushpred.learn_object_model(files, jobs=2, limit_surface="outline", pressure_shape="learned")
    run_cli(executable, "learn", *files, "--limit-surface", "outline", "--pressure-shape", "learned",
            "--out", tmp_path / "hex.json", "--jobs", 1)
    from_cli = json.loads((tmp_path / "hex.json").read_text())
    assert learned.limit_surface == "outline"
    assert learned.pressure_rim_weight_pushes == 4
    assert learned.pressure_rim_weight == from_cli["object"]["pressure_shape"]["rim_weight"]
    assert learned.pressure_rim_weight_standard_error > 0
    assert learned.to_dict()["parameters"] == from_cli["parameters"]
    # A version 4 file has no pressure shape: a uniform pressure.
    d = learned.to_dict()
    d["version"] = 4
    del d["object"]["pressure_shape"]
    assert pushpred.object_model_from_dict(d).pressure_rim_weight == 0.0
    with pytest.raises(pushpred.InputError, match="pressure shape"):
        pushpred.learn_object_model(files, limit_surface="outline", pressure_shape="conical")


def test_the_similarity_weighting_is_learned_as_the_cli_learns_it(executable, hex_files, model, tmp_path):
    # The default averages the weights over the bandwidths; "chosen" keeps one bandwidth, as `learn --similarity`.
    assert model.to_dict()["similarity_weighting"] == "averaged"
    chosen = pushpred.learn_object_model(hex_files, jobs=2, similarity="chosen")
    run_cli(executable, "learn", *hex_files, "--similarity", "chosen", "--out", tmp_path / "hex.json", "--jobs", 1)
    from_cli = json.loads((tmp_path / "hex.json").read_text())
    assert chosen.to_dict()["similarity_weighting"] == from_cli["similarity_weighting"] == "chosen"
    assert chosen.to_dict()["similarity_bandwidth"] == from_cli["similarity_bandwidth"]
    # The two weightings forecast the same plan differently (the learned pushes push unlike it).
    tip, direction = np.array([-0.066, 0.01]), np.array([1.0, 0.2])
    a = model.forecast(np.zeros(3), tip=tip, direction=direction, speed_m_s=0.05)["pose"][-1]
    b = chosen.forecast(np.zeros(3), tip=tip, direction=direction, speed_m_s=0.05)["pose"][-1]
    assert np.abs(a - b).max() > 1e-9
    with pytest.raises(pushpred.InputError, match="similarity"):
        pushpred.learn_object_model(hex_files, similarity="nearest")


def test_the_central_forecast_is_learned_as_the_cli_learns_it(executable, hex_files, model, tmp_path):
    # The default is the ensemble's mean; "ensemble_median" (its weighted geometric median in position, weighted median
    # in yaw) as `learn --central ensemble_median`, kept in the file and used by its forecast.
    assert model.to_dict()["central"] == "ensemble_mean"
    median = pushpred.learn_object_model(hex_files, jobs=2, central="ensemble_median")
    run_cli(executable, "learn", *hex_files, "--central", "ensemble_median", "--out", tmp_path / "hex.json",
            "--jobs", 1)
    from_cli = json.loads((tmp_path / "hex.json").read_text())
    assert median.to_dict()["central"] == from_cli["central"] == "ensemble_median"
    assert median.to_dict()["regions"] == from_cli["regions"]
    cli = cli_forecast(executable, tmp_path / "hex.json", tmp_path / "f")
    f = median.forecast(np.zeros(3), **PLAN)
    np.testing.assert_allclose(1e3 * f["pose"][:, 0], cli["x_mm"], atol=1e-6)
    np.testing.assert_allclose(np.rad2deg(f["pose"][:, 2]), cli["yaw_deg"], atol=1e-6)
    # The median is not the mean of the same ensemble.
    mean = model.forecast(np.zeros(3), times_s=f["t_s"], **PLAN)
    assert np.abs(mean["pose"] - f["pose"]).max() > 1e-6
    with pytest.raises(pushpred.InputError, match="central"):
        pushpred.learn_object_model(hex_files, central="mode")


def test_the_residual_correction_is_learned_as_the_cli_learns_it(executable, hex_files, model, tmp_path):
    # On by default; "loo" (the central forecast shifted by the learned pushes' leave-one-out final errors) as
    # `learn --residual-correction loo`, kept in the file (with each push's error) and used by its forecast; "none"
    # leaves the central forecast as it is.
    assert model.to_dict()["residual_correction"]["applied"] is True
    corrected = pushpred.learn_object_model(hex_files, jobs=2, residual_correction="loo")
    plain_model = pushpred.learn_object_model(hex_files, jobs=2, residual_correction="none")
    assert plain_model.to_dict()["residual_correction"]["applied"] is False
    assert corrected.to_dict()["residual_correction"] == model.to_dict()["residual_correction"]
    run_cli(executable, "learn", *hex_files, "--residual-correction", "loo", "--out", tmp_path / "hex.json",
            "--jobs", 1)
    from_cli = json.loads((tmp_path / "hex.json").read_text())
    assert from_cli["version"] == 7
    assert corrected.to_dict()["residual_correction"] == from_cli["residual_correction"]
    assert from_cli["residual_correction"]["applied"] is True
    np.testing.assert_allclose([p["loo_final_error"] for p in corrected.to_dict()["pushes"]],
                               [p["loo_final_error"] for p in from_cli["pushes"]], atol=1e-12)
    assert corrected.to_dict()["regions"] == from_cli["regions"]
    f = corrected.forecast(np.zeros(3), **PLAN)
    plain = plain_model.forecast(np.zeros(3), times_s=f["t_s"], **PLAN)
    # The shift is 0 at the start and grows with the tip's progress.
    np.testing.assert_allclose(f["pose"][0], plain["pose"][0], atol=1e-12)
    assert np.abs(f["pose"][-1] - plain["pose"][-1]).max() > 1e-6
    with pytest.raises(pushpred.InputError, match="residual correction"):
        pushpred.learn_object_model(hex_files, residual_correction="mean")


def test_the_measured_rod_friction_is_learned_as_the_cli_learns_it(executable, hex_files, tmp_path):
    # `learn --pusher-friction measured`: every learned push holds the median of what the force sensors measured, and
    # the file says so; the same from Python and the program.
    measured = pushpred.learn_object_model(hex_files, jobs=2, pusher_friction="measured")
    d = measured.to_dict()
    assert d["pusher_friction"]["method"].startswith("measured: ")
    assert len({p["pusher_friction"] for p in d["pushes"]}) == 1
    run_cli(executable, "learn", *hex_files, "--pusher-friction", "measured", "--out", tmp_path / "hex.json",
            "--jobs", "2")
    from_cli = json.loads((tmp_path / "hex.json").read_text())
    assert from_cli["pusher_friction"] == d["pusher_friction"]
    with pytest.raises(pushpred.InputError, match="pusher friction"):
        pushpred.learn_object_model(hex_files, pusher_friction="guessed")
