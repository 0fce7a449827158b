"""docs/PYTHON.md's tour runs as written: every ```python block of the page, in order and in one
namespace (as a reader would type them), on the tiny pipeline's outputs in place of the paths the
page names. A block that raises fails the test; the first block must write its figure. The
section "Three analyses" runs again on its own, as a reader copying just it would run it: its
figure written, its numbers those the reader's objects give.

    PYTHONPATH=python PILELAB_RUN=OUT /usr/bin/python3 -m unittest tests/python/test_docs_tour.py
"""
import os
import re
import tempfile
import unittest

import matplotlib

matplotlib.use("Agg")

OUT = os.environ.get("PILELAB_RUN", "")
PAGE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "docs", "PYTHON.md")


def python_blocks(text):
    return re.findall(r"```python\n(.*?)```", text, flags=re.S)


def section(text, title):
    """The text of the section "## title", up to the next heading of that level."""
    found = re.search(rf"^## {re.escape(title)}\n(.*?)(?=^## |\Z)", text, flags=re.S | re.M)
    return found.group(1) if found else ""


@unittest.skipUnless(OUT, "set PILELAB_RUN to a `pilelab run` output directory")
class DocsTour(unittest.TestCase):
    def run_blocks(self, blocks, where, namespace):
        """Runs blocks in order in namespace, in the current directory."""
        for i, block in enumerate(blocks):
            # The page's example paths (an ensemble, one pile) stand for any run directory.
            code = re.sub(r'"out/[A-Za-z0-9_-]+"', repr(OUT), block)
            with self.subTest(section=where, block=i):
                exec(compile(code, f"docs/PYTHON.md {where} block {i + 1}", "exec"), namespace)

    def in_temporary_directory(self):
        work = tempfile.TemporaryDirectory()
        self.addCleanup(work.cleanup)
        here = os.getcwd()
        os.chdir(work.name)
        self.addCleanup(os.chdir, here)
        return work.name

    def test_every_block_runs_on_a_real_run(self):
        with open(PAGE, encoding="utf-8") as f:
            blocks = python_blocks(f.read())
        self.assertGreaterEqual(len(blocks), 6, "the tour's three blocks and the three analyses")
        work = self.in_temporary_directory()
        self.run_blocks(blocks, "page", {})
        self.assertTrue(os.path.getsize(os.path.join(work, "base.png")) > 0, "the tour's figure")
        self.assertTrue(os.path.getsize(os.path.join(work, "base_x_over_R.png")) > 0, "the analyses' figure")

    def test_the_three_analyses_run_on_their_own(self):
        with open(PAGE, encoding="utf-8") as f:
            blocks = python_blocks(section(f.read(), "Three analyses"))
        self.assertEqual(len(blocks), 3, "base load against x/R, a grains DataFrame, the coordination number")
        work = self.in_temporary_directory()
        ns = {}
        self.run_blocks(blocks, '"Three analyses"', ns)
        self.assertTrue(os.path.getsize(os.path.join(work, "base_x_over_R.png")) > 0, "the analyses' figure")
        run, s, g = ns["run"], ns["s"], ns["g"]
        self.assertEqual(g, run.geometry())
        self.assertEqual(g.apex_x_m, run.report["dem"]["apex_x_m"])
        self.assertEqual(len(ns["grains"]), len(s))
        self.assertTrue(ns["grains"]["band"].between(0, 3).all(), "quarters of the height")
        self.assertEqual(len(ns["contacts"]), len(s.contacts))
        self.assertAlmostEqual(ns["z"], s.contact_count.mean(), delta=1e-12)
        self.assertLessEqual(ns["z_grains"], ns["z"])


if __name__ == "__main__":
    unittest.main()
