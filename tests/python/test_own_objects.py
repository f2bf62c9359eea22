"""A researcher's own objects and surfaces from Python: a shape dict wherever a shape name is accepted, the friction
coefficient as the keyword friction_coefficient, and a method that lacks a coefficient skipped with a note.

The checks hold an own object to the dataset's: the hexagon written out vertex by vertex as a polygon, and the
ellip1 disc as a circle, give the same study to the last bit as the dataset's names do."""
import math
import shutil

import pytest

import pushpred
from conftest import read_json, run_cli

HEX_AS_POLYGON = {
    "name": "myhex", "mass_kg": 0.9827, "inertia_kgm2": 0.001497, "centroid_m": [0, 0],
    "outline": {"kind": "polygon",
                "vertices_m": [[0.0605 * math.cos(math.pi / 3 * k), 0.0605 * math.sin(math.pi / 3 * k)]
                               for k in range(6)]},
}


def test_a_shape_dict_gives_the_same_push_and_study_as_the_dataset_name(hex_file):
    mine = pushpred.load_push(hex_file, shape=HEX_AS_POLYGON)
    theirs = pushpred.load_push(hex_file)
    assert mine.shape["name"] == "myhex" and mine.shape["own"] and mine.shape["geometry"] == "polygon"
    assert (mine.pose == theirs.pose).all()
    a = pushpred.run_prediction_study(mine)
    b = pushpred.run_prediction_study(theirs)
    for pa, pb in zip(a["phases"], b["phases"]):
        assert pa["errors"] == pb["errors"]


def test_a_circle_dict_is_the_dataset_disc(ellip_file):
    disc = {"name": "puck", "mass_kg": 0.8937, "inertia_kgm2": 0.001231,
            "outline": {"kind": "circle", "radius_m": 0.0525}}
    a = pushpred.run_prediction_study(pushpred.load_push(ellip_file, shape=disc))
    b = pushpred.run_prediction_study(pushpred.load_push(ellip_file))
    assert [p["errors"] for p in a["phases"]] == [p["errors"] for p in b["phases"]]


def test_a_polygon_without_a_centroid_has_its_area_centroid():
    # An L: a 40 x 20 mm bar with a 20 x 20 mm square on its left end. By hand, the area centroid is
    # (800 mm^2 (20, 10) + 400 mm^2 (10, 30)) / 1200 mm^2 = (50/3, 50/3) mm from the corner.
    shape = pushpred.shape_from_dict({
        "name": "ell", "mass_kg": 0.3, "inertia_kgm2": 1e-4,
        "outline": {"kind": "polygon", "vertices_m": [[0, 0], [0.04, 0], [0.04, 0.02], [0.02, 0.02], [0.02, 0.04],
                                                      [0, 0.04]]}})
    assert shape["centroid_m"] == pytest.approx([0.05 / 3, 0.05 / 3], abs=1e-15)
    assert shape["dim1_m"] == pytest.approx(0.04) and shape["dim2_m"] == pytest.approx(0.04)


@pytest.mark.parametrize("bad, message", [
    ({"name": "x", "mass_kg": -1, "inertia_kgm2": 1e-3, "outline": {"kind": "circle", "radius_m": 0.05}},
     "mass_kg must be positive"),
    ({"name": "x", "mass_kg": 1, "inertia_kgm2": 0, "outline": {"kind": "circle", "radius_m": 0.05}},
     "inertia_kgm2 must be positive"),
    ({"name": "x", "mass_kg": float("nan"), "inertia_kgm2": 1e-3, "outline": {"kind": "circle", "radius_m": 0.05}},
     "holds NaN or an infinity"),
    ({"name": "x", "mass_kg": 1, "inertia_kgm2": 1e-3,
      "outline": {"kind": "polygon", "vertices_m": [[0, 0], [0.1, 0]]}}, "at least 3 vertices"),
    ({"name": "x", "mass_kg": 1, "inertia_kgm2": 1e-3,
      "outline": {"kind": "polygon", "vertices_m": [[0, 0], [0.1, 0.1], [0.1, 0], [0, 0.1]]}}, "not a simple polygon"),
    ({"name": "x", "mass_kg": 1, "inertia_kgm2": 1e-3,
      "outline": {"kind": "polygon", "vertices_m": [[0, 0], [0, 0.1], [0.1, 0]]}}, "clockwise"),
    ({"name": "x", "mass_kg": 1, "inertia_kgm2": 1e-3, "outline": {"kind": "blob"}}, "'kind' must be"),
    ({"name": "x", "mass": 1, "inertia_kgm2": 1e-3, "outline": {"kind": "circle", "radius_m": 0.05}},
     "unknown field 'mass'"),
])
def test_a_bad_shape_dict_is_an_input_error_naming_the_argument(hex_file, bad, message):
    with pytest.raises(pushpred.InputError) as e:
        pushpred.load_push(hex_file, shape=bad)
    assert message in str(e.value) and str(e.value).startswith("shape")
    assert "--" not in str(e.value)


def test_an_unknown_shape_name_says_how_to_give_one(hex_file):
    with pytest.raises(pushpred.InputError, match="unknown shape 'teapot'.*shape file"):
        pushpred.load_push(hex_file, shape="teapot")


def test_an_own_surface_without_a_coefficient_skips_only_simple(hex_file, tmp_path, executable):
    # The same push, named as if recorded on a surface the library has no friction coefficient for.
    wood = tmp_path / hex_file.split("/")[-1].replace("surface=abs", "surface=wood")
    shutil.copy(hex_file, wood)
    study = pushpred.run_prediction_study(pushpred.load_push(str(wood)))
    for phase in study["phases"]:
        assert "simple" not in phase["errors"] and "dob" in phase["errors"]
        note = phase["method_notes"]["simple"]
        assert note.startswith("skipped: no friction coefficient known for surface 'wood'")
        assert "--mu" not in note
    # The other methods are the abs push's, and friction_coefficient= gives simple back.
    abs_study = pushpred.run_prediction_study(pushpred.load_push(hex_file))
    assert [p["errors"]["dob"] for p in study["phases"]] == [p["errors"]["dob"] for p in abs_study["phases"]]
    given = pushpred.run_prediction_study(pushpred.load_push(str(wood)), friction_coefficient=0.14)
    assert [p["errors"]["simple"] for p in given["phases"]] == [p["errors"]["simple"] for p in abs_study["phases"]]
    # The program says the same in summary.json and exits 0.
    run_cli(executable, "predict", wood, "--out", tmp_path / "p")
    cli = read_json(tmp_path / "p" / "summary.json")["files"][0]
    assert "simple" not in cli["phases"][0]["methods"]
    assert cli["phases"][0]["method_notes"]["simple"].startswith("skipped: ")


def test_use_shapes_makes_an_own_object_known_by_name(tmp_path):
    box = {"name": "ownbox7", "mass_kg": 0.5, "inertia_kgm2": 4e-4,
           "outline": {"kind": "rectangle", "sides_m": [0.06, 0.08]}}
    pushpred.use_shapes([box])
    assert pushpred.shapes()["ownbox7"]["own"]
    assert pushpred.shapes()["hex"]["own"] is False
    with pytest.raises(pushpred.InputError, match="shapes.json: no shapes|cannot open"):
        pushpred.use_shapes(str(tmp_path / "shapes.json"))
