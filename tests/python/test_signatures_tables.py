"""studies/signatures: the screen's paired effects on arms whose answers are planted exactly,
and the plate-load dip statistic of screen.py on profiles whose value is known.

    PYTHONPATH=python /usr/bin/python3 -m unittest tests/python/test_signatures_tables.py
"""
import importlib.util
import os
import sys
import unittest

import numpy as np

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
sys.path.insert(0, os.path.join(ROOT, "python"))


def module(name, path):
    spec = importlib.util.spec_from_file_location(name, os.path.join(ROOT, path))
    m = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(m)
    return m


tables = module("signatures_tables", "studies/signatures/tables.py")
screen = module("signatures_screen", "studies/signatures/screen.py")


def arm(values, loo):
    """An arm whose piles (seeds 1..n) have the given responses and whose ensemble statistic has
    the given leave-one-out values."""
    members = {s + 1: {"seed": s + 1, "repose_mean_deg": v} for s, v in enumerate(values)}
    base = {"seeds": list(range(1, len(values) + 1)), "quantities": {"q": [float(np.mean(loo)), 0.0]},
            "leave_one_out": {"q": list(loo)}}
    return {"members": members, "base": base}


class PairedEffects(unittest.TestCase):
    def test_a_planted_effect_is_found_with_the_paired_error(self):
        # Each seed shifts every arm alike; the arms add 1.0 (force point) and 0.25 (history).
        rng = np.random.default_rng(3)
        seed_effect = rng.normal(27, 2, 12)
        noise = [rng.normal(0, 0.1, 12) for _ in range(4)]
        planted = [1.0 + 0.25, 1.0, 0.25, 0.0]  # (cs, ct, ms, mt) as tables.ARMS
        arms = [arm(seed_effect + p + n, np.zeros(12)) for p, n in zip(planted, noise)]
        v, s, n = tables.paired(arms, "repose_mean_deg", [0.5, 0.5, -0.5, -0.5])
        contrast = 0.5 * (noise[0] + noise[1] - noise[2] - noise[3])
        self.assertEqual(n, 12)
        self.assertAlmostEqual(v, 1.0 + contrast.mean(), places=12)
        self.assertAlmostEqual(s, contrast.std(ddof=1) / np.sqrt(12), places=12)
        # The seed effect (sd 2) cancels: the error is that of the noise, far below 2 / sqrt(12).
        self.assertLess(s, 0.1)
        v, s, n = tables.paired(arms, "repose_mean_deg", [0.5, -0.5, 0.5, -0.5])
        self.assertLess(abs(v - 0.25), 3 * s)

    def test_the_jackknife_contrast_of_a_mean_is_its_paired_standard_error(self):
        # For a mean over seeds the jackknife error of a contrast equals the paired sd / sqrt(n).
        rng = np.random.default_rng(5)
        a, b = rng.normal(0, 1, 10), rng.normal(0, 1, 10)
        loo = lambda x: np.array([(x.sum() - x[k]) / (len(x) - 1) for k in range(len(x))])
        arms = [arm(np.zeros(10), loo(a)), arm(np.zeros(10), loo(b))]
        v, s, n = tables.paired_fields(arms, "q", [1, -1])
        self.assertAlmostEqual(v, a.mean() - b.mean(), places=12)
        self.assertAlmostEqual(s, (a - b).std(ddof=1) / np.sqrt(10), places=12)


class DipStatistic(unittest.TestCase):
    def test_known_profiles(self):
        x = 0.5 * (screen.BINS[1:] + screen.BINS[:-1])
        self.assertAlmostEqual(screen.centre_over_ring(x, np.ones_like(x)), 0.0, places=12)
        wedge = np.clip(1 - np.abs(x), 0, None)
        # The bins' centres in the windows: |x'| = 0.025, 0.075 and 0.175 ... 0.325.
        centre = 1 - np.mean([0.025, 0.075])
        ring = 1 - np.mean([0.175, 0.225, 0.275, 0.325])
        self.assertAlmostEqual(screen.centre_over_ring(x, wedge), centre / ring - 1, places=12)
        dipped = np.where(np.abs(x) < 0.1, 0.5, 1.0)
        self.assertAlmostEqual(screen.centre_over_ring(x, dipped), -0.5, places=12)
        self.assertIsNone(screen.centre_over_ring(x, np.where(np.abs(x) < 0.1, 1.0, 0.0)))


if __name__ == "__main__":
    unittest.main()


factorial = module("signatures_factorial", "studies/signatures/factorial.py")


class FactorialEffects(unittest.TestCase):
    """The second screen's effects on 16 cells whose responses are planted: main effects exact
    where the within-cell noise is zero, and the standard error the textbook s sqrt(1/16 + 1/16)."""

    def cells(self, planted, noise_sd, seeds=4, rng=None):
        cells = []
        for levels in factorial.design.design():
            rows = []
            for s in range(seeds):
                y = 25.0 + sum(0.5 * planted.get(f, 0.0) * levels[f] for f in "ABCDEF")
                y += rng.normal(0, noise_sd) if rng is not None else 0.0
                rows.append({"repose_mean_deg": y})
            cells.append({"levels": levels, "rows": rows})
        return cells

    def test_planted_main_effects_are_recovered_exactly(self):
        planted = {"A": 1.0, "C": -3.0, "F": 0.5}
        cells = self.cells(planted, 0.0)
        for f in "ABCDEF":
            y, cell, levels = factorial.column(cells, "repose_mean_deg")
            v, _ = factorial.contrast(y, cell, np.array([lv[f] for lv in levels], dtype=float))
            self.assertAlmostEqual(v, planted.get(f, 0.0), places=12, msg=f)

    def test_the_error_is_the_pooled_within_cell_spread(self):
        rng = np.random.default_rng(11)
        cells = self.cells({"B": 2.0}, 1.0, seeds=4, rng=rng)
        y, cell, levels = factorial.column(cells, "repose_mean_deg")
        v, s = factorial.contrast(y, cell, np.array([lv["B"] for lv in levels], dtype=float))
        resid = np.concatenate([y[cell == k] - y[cell == k].mean() for k in range(16)])
        pooled = np.sqrt((resid ** 2).sum() / (64 - 16))
        self.assertAlmostEqual(s, pooled * np.sqrt(2 / 32), places=12)
        self.assertLess(abs(v - 2.0), 3 * s)  # the planted effect within its error
        # A two-factor chain with nothing planted is within its error too (the design keeps
        # main effects off the chains).
        v, s = factorial.contrast(y, cell, np.array([lv["A"] * lv["B"] for lv in levels], dtype=float))
        self.assertLess(abs(v), 3 * s)
