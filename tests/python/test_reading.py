"""Reading a push: the module's arrays against `pushpred inspect --json`, and the library's errors."""
import numpy as np
import pytest

import pushpred
from conftest import run_cli
import json


def test_push_arrays_have_units_and_shapes(hex_file):
    push = pushpred.load_push(hex_file)
    n = len(push)
    assert n > 100
    assert push.t_s.shape == (n,)
    assert push.pose.shape == (n, 3)
    assert push.force_N.shape == (n, 2)
    assert push.tip_m.shape == (n, 2)
    assert push.in_contact.dtype == np.bool_ and push.in_contact.shape == (n,)
    np.testing.assert_allclose(np.diff(push.t_s), 1.0 / push.rate_hz, rtol=1e-9)
    np.testing.assert_array_equal(push.x_m, push.pose[:, 0])
    np.testing.assert_array_equal(push.yaw_rad, push.pose[:, 2])
    u = push.applied_input()
    np.testing.assert_array_equal(u[:, :2], push.force_N)
    np.testing.assert_array_equal(u[:, 2], push.torque_about_centre_Nm)
    assert push.parameters["shape"] == "hex" and push.parameters["speed_m_s"] == pytest.approx(0.05)
    assert push.shape["mass_kg"] > 0
    # Views are read-only: a push is the library's record, not a scratch buffer.
    with pytest.raises(ValueError):
        push.t_s[0] = 1.0


def test_inspection_matches_the_cli(executable, hex_file, ellip_file):
    proc = run_cli(executable, "inspect", hex_file, ellip_file, "--json")
    cli = {entry["source"]: entry for entry in json.loads(proc.stdout)["files"]}
    for path in (hex_file, ellip_file):
        mine = pushpred.inspect(pushpred.load_push(path))
        theirs = cli[path]
        for key in ("duration_s", "travel_mm", "rotation_deg", "mean_contact_force_N"):
            assert mine[key] == pytest.approx(theirs[key], rel=1e-9, abs=1e-12), key
        assert mine["flags"] == theirs["flags"]


def test_raw_streams_and_push_from_streams_agree_with_load_push(hex_file):
    raw = pushpred.read_recording(hex_file)
    assert raw["parameters"]["shape"] == "hex"
    streams = {}
    for name, cols in (("tip_pose", ("x_m", "y_m", "yaw_rad")), ("object_pose", ("x_m", "y_m", "yaw_rad")),
                       ("ft_wrench", ("fx_N", "fy_N", "tz_Nm"))):
        s = raw[name]
        streams[name] = np.column_stack([s["t_s"]] + [s[c] for c in cols])
    rebuilt = pushpred.push_from_streams(streams["tip_pose"], streams["object_pose"], streams["ft_wrench"],
                                         shape="hex")
    direct = pushpred.load_push(hex_file)
    np.testing.assert_array_equal(rebuilt.pose, direct.pose)
    np.testing.assert_array_equal(rebuilt.force_N, direct.force_N)


def test_errors_are_python_exceptions_with_the_library_message(tmp_path):
    missing = tmp_path / "nowhere.h5"
    with pytest.raises(pushpred.InputError) as e:
        pushpred.load_push(str(missing))
    assert "nowhere.h5" in str(e.value)
    assert isinstance(e.value, ValueError)
    bad = tmp_path / "motion_surface=abs_shape=hex_a=0_v=20_i=0.000_s=0.700_t=0.000.json"
    bad.write_text('{"tip_pose": [[0, 1, 2]]}')
    with pytest.raises(pushpred.InputError) as e:
        pushpred.load_push(str(bad))
    assert bad.name in str(e.value)
    with pytest.raises(pushpred.InputError, match="unknown shape 'cube'"):
        pushpred.push_from_streams(*_streams_of_a_real_push(), shape="cube")
    with pytest.raises(pushpred.InputError, match="3 columns"):
        pushpred.least_squares_relation(np.zeros((5, 2)), np.zeros((5, 2)))


def test_hostile_inputs_are_input_errors_naming_the_problem(hex_file, tmp_path):
    """A truncated HDF5 file says so, a resampling or plan rate of 1e9 Hz is refused before it asks for billions of
    samples (it was a MemoryError or worse), and a shape dict holding NaN names the argument."""
    cut = tmp_path / "motion_surface=abs_shape=hex_a=0_v=50_i=4.000_s=0.700_t=0.000.h5"
    whole = open(hex_file, "rb").read()
    cut.write_bytes(whole[: len(whole) // 2])
    with pytest.raises(pushpred.InputError, match=f"{cut.name}: not a complete HDF5 file: it holds"):
        pushpred.load_push(str(cut))
    with pytest.raises(pushpred.InputError, match="resampling rate of 1e\\+09 Hz is above the 2500 Hz"):
        pushpred.load_push(hex_file, rate_hz=1e9)
    push = pushpred.load_push(hex_file)
    with pytest.raises(pushpred.InputError, match="planned-force rate of 1e\\+09 Hz is above the push's grid rate"):
        pushpred.run_prediction_study(push, plan_rate_hz=1e9)
    with pytest.raises(pushpred.InputError, match="shape: holds NaN or an infinity"):
        pushpred.shape_from_dict({"name": "x", "mass_kg": float("nan"), "inertia_kgm2": 0.001,
                                  "outline": {"kind": "circle", "radius_m": 0.05}})


def _streams_of_a_real_push():
    import os
    raw = pushpred.read_recording(os.path.join(pushpred.data_folder(), "abs",
                                               "motion_surface=abs_shape=hex_a=0_v=50_i=4.000_s=0.700_t=0.000.h5"))
    out = []
    for name, cols in (("tip_pose", ("x_m", "y_m", "yaw_rad")), ("object_pose", ("x_m", "y_m", "yaw_rad")),
                       ("ft_wrench", ("fx_N", "fy_N", "tz_Nm"))):
        out.append(np.column_stack([raw[name]["t_s"]] + [raw[name][c] for c in cols]))
    return out



def test_recordings_and_batches(data_dir, tmp_path):
    files = pushpred.recordings(surface="abs")
    assert files == sorted(str(p) for p in (data_dir / "abs").glob("*.h5"))
    missing = tmp_path / "missing.h5"
    calls = []
    results, failures = pushpred.run_batch([files[0], missing], pushpred.load_push,
                                           progress=lambda i, n, path, error: calls.append((i, n, error is None)))
    assert [p for p, _ in results] == [files[0]] and len(results[0][1]) > 0
    # The reason is the library's message without the path it names first.
    path, reason = failures[0]
    assert path == str(missing) and reason and not reason.startswith(str(missing))
    with pytest.raises(pushpred.InputError, match=f"{missing}: {reason}"):
        pushpred.load_push(missing)
    assert calls == [(1, 2, True), (2, 2, False)]
