"""strider.GP against scikit-learn's exact GP with the same fixed hyperparameters."""

import numpy as np
import pytest

import strider

sklearn_gp = pytest.importorskip("sklearn.gaussian_process")
kernels = pytest.importorskip("sklearn.gaussian_process.kernels")


def data(n=60, d=3, seed=7):
    rng = np.random.default_rng(seed)
    x = rng.uniform(-1, 1, size=(n, d))
    y = np.sin(3 * x[:, 0]) + 0.5 * x[:, 1] ** 2 - x[:, 2] + rng.normal(0, 0.1, n)
    q = rng.uniform(-1.2, 1.2, size=(40, d))
    return x, y, q


@pytest.mark.parametrize(
    "kind,sk",
    [
        ("se", lambda l: kernels.RBF(length_scale=l, length_scale_bounds="fixed")),
        ("matern32", lambda l: kernels.Matern(length_scale=l, nu=1.5, length_scale_bounds="fixed")),
        ("matern52", lambda l: kernels.Matern(length_scale=l, nu=2.5, length_scale_bounds="fixed")),
        ("exp", lambda l: kernels.Matern(length_scale=l, nu=0.5, length_scale_bounds="fixed")),
    ],
)
def test_gp_agrees_with_scikit_learn(kind, sk):
    x, y, q = data()
    ls, sv, nv = 0.7, 1.3, 0.05
    gp = strider.GP(kernel=kind, lengthscale=ls, signal_variance=sv, noise_variance=nv)
    mean, var = gp.fit(x, y).predict(q)
    kernel = kernels.ConstantKernel(sv, constant_value_bounds="fixed") * sk(ls)
    ref = sklearn_gp.GaussianProcessRegressor(kernel=kernel, alpha=nv, optimizer=None)
    ref.fit(x, y)
    m_ref, s_ref = ref.predict(q, return_std=True)
    np.testing.assert_allclose(mean, m_ref, rtol=0, atol=1e-9)
    np.testing.assert_allclose(var, s_ref**2, rtol=0, atol=1e-9)


def test_add_and_remove_points_match_a_refit():
    x, y, q = data(n=30)
    inc = strider.GP(lengthscale=0.5, noise_variance=0.1).fit(x[:20], y[:20])
    for i in range(20, 30):
        inc.add_point(x[i], y[i])
    inc.remove_point(3)
    keep = [i for i in range(30) if i != 3]
    ref = strider.GP(lengthscale=0.5, noise_variance=0.1).fit(x[keep], y[keep])
    assert len(inc) == 29
    for a, b in zip(inc.predict(q), ref.predict(q)):
        np.testing.assert_allclose(a, b, rtol=0, atol=1e-9)


def test_hyperparameter_fit_raises_the_likelihood():
    x, y, _ = data(n=50)
    gp = strider.GP(lengthscale=5.0, signal_variance=0.1, noise_variance=1.0).fit(x, y)
    before = gp.log_marginal_likelihood()
    gp.fit_hyperparameters()
    assert gp.log_marginal_likelihood() > before + 1.0
    assert gp.noise_variance < 1.0


def test_bad_input_is_a_value_error():
    with pytest.raises(ValueError, match="unknown kernel"):
        strider.GP(kernel="rbf")
    with pytest.raises(ValueError, match="lengthscale -1"):
        strider.GP(lengthscale=-1.0)
    gp = strider.GP()
    with pytest.raises(ValueError, match="no data"):
        gp.predict(np.zeros((1, 2)))
    with pytest.raises(ValueError, match="finite"):
        gp.fit(np.array([[np.nan, 0.0]]), np.array([1.0]))
    gp.fit(np.zeros((2, 2)) + [[0, 0], [1, 1]], np.array([1.0, 2.0]))
    with pytest.raises(ValueError, match="columns"):
        gp.predict(np.zeros((1, 3)))
    with pytest.raises(ValueError, match="out of range"):
        gp.remove_point(5)
