"""docs/PYTHON.md's tour runs as written: every ```python block of the page, in order and in one
namespace (as a reader would type them), on the tiny pipeline's outputs in place of the paths the
page names. A block that raises fails the test; the first block must write its figure.

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


@unittest.skipUnless(OUT, "set PILELAB_RUN to a `pilelab run` output directory")
class DocsTour(unittest.TestCase):
    def test_every_block_runs_on_a_real_run(self):
        with open(PAGE, encoding="utf-8") as f:
            blocks = python_blocks(f.read())
        self.assertGreaterEqual(len(blocks), 3, "the tour has its three blocks")
        namespace = {}
        here = os.getcwd()
        with tempfile.TemporaryDirectory() as work:
            os.chdir(work)
            try:
                for i, block in enumerate(blocks):
                    # The page's example paths (an ensemble, one pile) stand for any run directory.
                    code = re.sub(r'"out/[A-Za-z0-9_-]+"', repr(OUT), block)
                    with self.subTest(block=i):
                        exec(compile(code, f"docs/PYTHON.md block {i + 1}", "exec"), namespace)
                self.assertTrue(os.path.getsize(os.path.join(work, "base.png")) > 0, "the tour's figure")
            finally:
                os.chdir(here)


if __name__ == "__main__":
    unittest.main()
