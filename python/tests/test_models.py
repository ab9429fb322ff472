"""strider.RBCM against the committee formulas over strider.GP experts, and strider.CostModel
learning two terrains on a fused map."""

import numpy as np
import pytest

import strider

KW = dict(lengthscale=0.7, signal_variance=1.3, noise_variance=0.05)


def data(n=60, d=2, seed=4):
    rng = np.random.default_rng(seed)
    X = rng.uniform(-2, 2, (n, d))
    return X, np.sin(X[:, 0]) + 0.5 * X[:, 1] + 0.05 * rng.standard_normal(n)


def test_a_one_expert_bcm_is_the_gp():
    X, y = data()
    Q = data(15, seed=9)[0]
    r = strider.RBCM(2, m_max=len(X), m_min=1, variant="bcm", **KW).add(X, y)
    g = strider.GP(**KW).fit(X, y)
    for a, b in zip(r.predict(Q), g.predict(Q)):
        np.testing.assert_allclose(a, b, rtol=1e-10, atol=1e-12)
    assert len(r) == len(X) and r.experts == (1, 1)


@pytest.mark.parametrize("variant", ["robust", "bcm"])
def test_the_committee_combines_its_experts_by_prägr19_eq_8_and_9(variant):
    X, y = data(50)
    Q = data(20, seed=11)[0]
    # 50 points, 20 per expert, m_min 15: experts of 20, 20 and 10 points; the last sits out.
    r = strider.RBCM(2, m_max=20, m_min=15, variant=variant, **KW).add(X, y)
    assert r.experts == (3, 2)
    kss = KW["signal_variance"]
    prec, num, beta_sum = np.zeros(len(Q)), np.zeros(len(Q)), np.zeros(len(Q))
    for part in (slice(0, 20), slice(20, 40)):
        mu, var = strider.GP(**KW).fit(X[part], y[part]).predict(Q)
        beta = 0.5 * (np.log(kss) - np.log(var)) if variant == "robust" else np.ones(len(Q))
        beta = np.maximum(beta, 0.0)
        prec += beta / var
        num += beta * mu / var
        beta_sum += beta
    prec += (1 - beta_sum) / kss
    mean, var = r.predict(Q)
    np.testing.assert_allclose(var, 1 / prec, rtol=1e-9)
    np.testing.assert_allclose(mean, num / prec, rtol=1e-9, atol=1e-12)


def test_bad_committees_are_value_errors():
    with pytest.raises(ValueError, match="m_max"):
        strider.RBCM(2, m_max=0)
    with pytest.raises(ValueError, match="variant"):
        strider.RBCM(2, variant="robustest")
    r = strider.RBCM(2)
    with pytest.raises(ValueError, match="columns"):
        r.predict(np.zeros((3, 3)))
    with pytest.raises(ValueError, match="finite"):
        r.add(np.zeros((1, 2)), np.array([np.nan]))
    # Before any expert has m_min points the committee predicts the prior.
    mean, var = r.add(*data(5)).predict(np.zeros((1, 2)))
    assert mean[0] == 0.0 and var[0] == pytest.approx(1.0)


def two_terrains():
    """A 3 × 2 m flat patch, grey west of x = 1.5 and green east of it, fused from above."""
    m = strider.ElevationMap({"cell_size": 0.05})
    gx, gy = np.meshgrid(np.arange(0.0, 3.0, 0.02), np.arange(0.0, 2.0, 0.02))
    pts = np.column_stack([gx.ravel(), gy.ravel(), np.zeros(gx.size)]).astype(np.float32)
    cols = np.where(pts[:, :1] < 1.5, [[120, 120, 120]], [[40, 150, 40]]).astype(np.uint8)
    m.fuse(pts, cols, pose=(1.5, 1.0, 0.5), world_frame=True)
    return m


def test_the_cost_model_learns_two_terrains_and_classes_them():
    m = two_terrains()
    model = strider.CostModel(m, seed=2)
    rng = np.random.default_rng(5)
    for _ in range(4):
        for x, y in rng.uniform([0.3, 0.3], [2.7, 1.7], (40, 2)):
            model.measure(x, y, 1.2 if x < 1.5 else 4.0)
        u = model.update()
    assert model.learning_set >= 25 and model.measured_cells > 0
    assert u["classes"] and all(c["cells"] > 0 for c in u["classes"])
    L = m.layers()
    costs, classes = model.costs(), model.classes()
    assert costs.shape == classes.shape == L["observed"].shape
    xs = L["origin"][0] + (np.arange(costs.shape[1]) + 0.5) * L["cell_size"]
    row = costs.shape[0] // 2
    west = costs[row, (xs > 0.4) & (xs < 1.1)]
    east = costs[row, (xs > 1.9) & (xs < 2.6)]
    assert np.median(west) < 2.0 < 3.0 < np.median(east)
    cw = classes[row, (xs > 0.4) & (xs < 1.1)]
    ce = classes[row, (xs > 1.9) & (xs < 2.6)]
    assert np.bincount(cw[cw >= 0]).argmax() != np.bincount(ce[ce >= 0]).argmax()


def test_bad_cost_measurements_are_value_errors():
    m = two_terrains()
    model = strider.CostModel(m)
    with pytest.raises(ValueError, match="not a point"):
        model.measure(float("nan"), 0.0, 1.0)
    with pytest.raises(ValueError, match="measure"):
        model.measure(1.0, 1.0, float("inf"))
    with pytest.raises(ValueError, match="columns"):
        model.predict(np.zeros((2, 5)))
    with pytest.raises(ValueError, match="c_max"):
        strider.CostModel(m, c_max=0.5)
