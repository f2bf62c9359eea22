"""Relation estimators on a real push's observer output: RLS equals the batch least squares (lambda = 1), the Ceres
fit equals them, and the module gives what `pushpred predict` reports for the same intervals."""
import numpy as np
import pytest

import pushpred


@pytest.fixture(scope="module")
def intervals(hex_file):
    push = pushpred.load_push(hex_file)
    edges = np.linspace(0.0, push.duration_s, 5)
    return [pushpred.estimate_disturbance(push, "dob", edges[i], edges[i + 1]) for i in range(4)]


def test_rls_equals_least_squares_and_the_ceres_fit(intervals):
    rls = pushpred.RecursiveLeastSquares()
    batch = pushpred.BatchLeastSquaresFit()
    for e in intervals:
        rls.add_estimate(e)
        batch.add_interval(e["u"], e["d_hat"])
    u = np.vstack([e["u"] for e in intervals])
    d = np.vstack([e["d_hat"] for e in intervals])
    reference = pushpred.least_squares_relation(u, d)
    for fit in (rls.parameters(), batch.parameters()):
        np.testing.assert_allclose(fit["beta"], reference["beta"], rtol=1e-7, atol=1e-9)
        np.testing.assert_allclose(fit["eps"], reference["eps"], rtol=1e-7, atol=1e-9)
        assert fit["samples"] == len(u)
    # And against numpy's own least squares, channel by channel.
    for c in range(3):
        H = np.column_stack([u[:, c], np.ones(len(u))])
        beta, eps = np.linalg.lstsq(H, d[:, c], rcond=None)[0]
        assert reference["beta"][c] == pytest.approx(beta, rel=1e-8, abs=1e-10)
        assert reference["eps"][c] == pytest.approx(eps, rel=1e-8, abs=1e-10)


def test_forgetting_robust_losses_and_readiness(intervals):
    names = pushpred.relation_estimator_names()
    assert {"rls", "rls_forget", "batch", "batch_huber"} <= set(names)
    for name in names:
        estimator = pushpred.relation_estimator(name)
        assert estimator.name == name
        assert not estimator.ready and estimator.not_ready_reason
        with pytest.raises(pushpred.InputError, match="not ready"):
            estimator.parameters()
        for e in intervals:
            estimator.add_estimate(e)
        assert estimator.ready
        assert np.all(np.isfinite(estimator.parameters()["beta"]))
    forget = pushpred.RecursiveLeastSquares(forgetting=0.5)
    plain = pushpred.RecursiveLeastSquares()
    for e in intervals:
        forget.add_estimate(e)
        plain.add_estimate(e)
    assert forget.parameters()["effective_samples"] < plain.parameters()["effective_samples"]
    huber = pushpred.BatchLeastSquaresFit(loss="huber")
    huber.add_interval(intervals[0]["u"], intervals[0]["d_hat"])
    assert huber.name == "batch_huber" and np.all(huber.parameters()["loss_scale"] > 0)
    with pytest.raises(pushpred.InputError, match="forgetting"):
        pushpred.RecursiveLeastSquares(forgetting=1.5)
    with pytest.raises(pushpred.InputError, match="loss"):
        pushpred.BatchLeastSquaresFit(loss="l1")
    clone = plain.clone()
    plain.reset()
    assert clone.ready and not plain.ready
