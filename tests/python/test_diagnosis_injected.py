"""The diagnosis on real pushes with an effect written into them here: data no simulator of the project made.

The hexagon's real ABS pushes (14, every one with a live force sensor; butter's 40 for the bias) are read as stored,
one sensor effect is added to the force stream, and the pushes are diagnosed through the module. What the real data already hold (their
own small delay and bias) is measured on a clean copy read the same way, so the checks are on the difference.
scripts/inject-real-effects.py runs the same study over four objects and two amounts of each effect
(docs/diagnosis.md, "Real pushes with an injected effect")."""
import numpy as np
import pytest

import pushpred


def real_pushes(data_dir, shape, delay_s=0.0, bias_x_N=0.0):
    """The object's real ABS pushes, the force stamps `delay_s` later and `bias_x_N` added to the force's x."""
    pushes = []
    for path in sorted((data_dir / "abs").glob("*_shape=%s_*.h5" % shape)):
        r = pushpred.read_recording(path)
        streams = {}
        for name in ("tip_pose", "object_pose", "ft_wrench"):
            columns = np.column_stack([np.asarray(v, dtype=float) for v in r[name].values()])
            if name == "ft_wrench":
                columns[:, 0] += delay_s
                columns[:, 1] += bias_x_N
            streams[name] = columns
        pushes.append(pushpred.push_from_streams(streams["tip_pose"], streams["object_pose"], streams["ft_wrench"],
                                                 source=path.name))
    return pushes


def hex_pushes(data_dir, delay_s=0.0):
    pushes = real_pushes(data_dir, "hex", delay_s=delay_s)
    assert len(pushes) == 14
    return pushes


def effect(report, kind):
    return next(e for e in report["effects"] if e["kind"] == kind)


@pytest.fixture(scope="module")
def clean(data_dir):
    return pushpred.diagnose(hex_pushes(data_dir))


def test_a_force_delay_written_into_real_pushes_is_found_with_its_amount(data_dir, clean):
    assert "time_offset" not in clean["found"]
    delayed = pushpred.diagnose(hex_pushes(data_dir, delay_s=0.03))
    assert "time_offset" in delayed["found"], delayed["findings"]
    added = effect(delayed, "time_offset")["parameters"]["delay"]["value"] - \
        effect(clean, "time_offset")["parameters"]["delay"]["value"]
    # The fit's own standard error is about 0.4 ms here; 2 ms is five of them and a quarter of a force sample.
    assert added == pytest.approx(0.03, abs=0.002)
    # The corrected model still beats the paper's method and both naive references on the held-out phases.
    after = delayed["error_after"]["pos_mm_mean"]
    assert after < delayed["error_before"]["pos_mm_mean"]
    assert after < delayed["error_references"]["hold"]["pos_mm_mean"]
    assert after < delayed["error_references"]["const_velocity"]["pos_mm_mean"]


def test_a_force_bias_written_into_real_pushes_moves_the_fitted_bias_by_that_amount(data_dir):
    # On butter, whose shape table lists no outline, which pushes rest clear does not depend on the force; on an
    # outlined object a bias can turn a rest force into the contact's cone or out of it (samples_without_contact),
    # and the pushes it is measured on change with it.
    clean = pushpred.diagnose(real_pushes(data_dir, "butter"))
    biased = pushpred.diagnose(real_pushes(data_dir, "butter", bias_x_N=1.0))
    before = effect(clean, "force_offset")["parameters"]
    after = effect(biased, "force_offset")["parameters"]
    assert after["bias_x"]["value"] - before["bias_x"]["value"] == pytest.approx(1.0, abs=0.02)
    assert after["bias_y"]["value"] == pytest.approx(before["bias_y"]["value"], abs=0.02)
