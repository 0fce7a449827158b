"""studies/paper/tables.py's statistics on ensembles whose answers are known exactly: the
jackknife error of a linear statistic (a regional mean) is the sample standard error of the
piles' own values, sd / sqrt(n); principal axes of known tensors; the regions of the wedge.

    PYTHONPATH=python /usr/bin/python3 -m unittest tests/python/test_paper_tables.py
"""
import importlib.util
import os
import unittest

import numpy as np

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
spec = importlib.util.spec_from_file_location("tables", os.path.join(ROOT, "studies", "paper", "tables.py"))
tables = importlib.util.module_from_spec(spec)
spec.loader.exec_module(tables)


def synthetic_ensemble(values_per_pile):
    """A wedge of height 1 and half-width 1 sampled at random points, each pile's fields a
    constant (stress: uniaxial vertical compression times the pile's value)."""
    e = tables.Ensemble.__new__(tables.Ensemble)
    rng = np.random.default_rng(7)
    x = rng.uniform(-1, 1, 4000)
    y = rng.uniform(0, 1, 4000) * (1 - np.abs(x))
    e.points = np.column_stack([x, y])
    e.h, e.apex, e.R = 1.0, 0.0, 1.0
    e.xr, e.yh = x, y
    e.attrs = {"rve_radius_m": 0.05}
    e.piles = {}
    for k, v in enumerate(values_per_pile):
        ones = np.ones_like(x)
        e.piles[k] = {"volume_fraction": v * ones, "stress_xx": 0 * ones, "stress_yy": -v * ones,
                      "stress_xy": 0 * ones}
    e.n = len(e.piles)
    return e


class PaperTables(unittest.TestCase):
    def test_jackknife_of_a_mean_is_the_standard_error(self):
        values = np.array([0.80, 0.83, 0.79, 0.85, 0.81])
        e = synthetic_ensemble(values)
        v, s = e.statistic(lambda F: F.mean(F["volume_fraction"], e.core()))
        self.assertAlmostEqual(v[0], values.mean(), places=12)
        self.assertAlmostEqual(s[0], values.std(ddof=1) / np.sqrt(len(values)), places=12)

    def test_vertical_compression_has_a_vertical_axis_and_full_anisotropy(self):
        e = synthetic_ensemble([1.0, 2.0])
        F = tables.Fields(e, e.mean_fields([0, 1]))
        anisotropy, tilt = F.axes("stress")
        np.testing.assert_allclose(anisotropy, 1.0)
        np.testing.assert_allclose(tilt, 0.0, atol=1e-12)

    def test_regions_lie_where_their_definitions_say(self):
        e = synthetic_ensemble([1.0, 2.0])
        self.assertTrue(np.all(np.abs(e.xr[e.core()]) < 0.15))
        depth = 1 - np.abs(e.xr) - e.yh
        self.assertTrue(np.all((depth[e.outer_layer()] > 0.05) & (depth[e.outer_layer()] < 0.1)))
        self.assertTrue(np.all(depth[e.interior()] > 0.05))
        self.assertTrue(np.all(e.xr[e.flanks(-1)] < 0) and np.all(e.xr[e.flanks(1)] > 0))


if __name__ == "__main__":
    unittest.main()
