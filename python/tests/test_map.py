"""strider.ElevationMap on its own: fusing numpy points and reading layers."""

import numpy as np
import pytest

import strider


def plane(n=4000, z=0.2, seed=1):
    rng = np.random.default_rng(seed)
    pts = np.column_stack([rng.uniform(0.3, 2.0, n), rng.uniform(-0.8, 0.8, n), np.full(n, z)])
    cols = np.tile(np.array([[30, 160, 40]], dtype=np.uint8), (n, 1))
    return pts.astype(np.float32), cols


def test_a_fused_plane_has_its_height_and_colour():
    m = strider.ElevationMap({"cell_size": 0.1})
    pts, cols = plane(z=-0.3)
    stats = m.fuse(pts, cols, pose=(1.0, 2.0, 0.5, np.pi / 2))
    assert stats["fused_points"] > 0
    L = m.layers()
    obs = L["observed"]
    assert obs.sum() == m.observed_cells > 0
    np.testing.assert_allclose(L["elevation"][obs], 0.2, atol=0.02)  # 0.5 - 0.3
    assert (L["color"][obs] == [30, 160, 40]).all()
    # Turned by 90°: the points ahead of the sensor lie north of it, at y in [2.3, 4.0].
    ys = L["origin"][1] + (np.nonzero(obs)[0] + 0.5) * L["cell_size"]
    assert ys.min() > 2.0 and ys.max() < 4.2


def test_bad_scans_and_parameters_are_value_errors():
    m = strider.ElevationMap()
    pts, cols = plane(n=10)
    with pytest.raises(ValueError, match="N × 3"):
        m.fuse(pts[:, :2].copy(), cols, pose=(0, 0, 0))
    with pytest.raises(ValueError, match="pose"):
        m.fuse(pts, cols, pose=(0, 0))
    with pytest.raises(ValueError, match="finite"):
        m.fuse(pts, cols, pose=(0, 0, float("nan")))
    with pytest.raises(ValueError, match="unknown parameter"):
        strider.ElevationMap({"cell_sise": 0.1})
    with pytest.raises(ValueError):
        strider.ElevationMap({"cell_size": -1.0})
    # Non-finite points are skipped and counted, never an error.
    pts[0] = np.nan
    assert m.fuse(pts, cols, pose=(0, 0, 0.5))["skipped_non_finite"] == 1
