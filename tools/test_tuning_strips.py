"""Tests of tools/tuning_strips.py: `python3 -m unittest tools/test_tuning_strips.py` (run by .ci/run).

The tuning strips are what the anytime rounds' settings are chosen on, so a measurement made on
them has to be one anyone can repeat: the same files on every run, nothing a user wrote
overwritten, and parts the nester can take (simple rings that fit across the strip).
"""

import json
import subprocess
import sys
import tempfile
import unittest
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parent))
from tuning_strips import area  # noqa: E402  (the script's own area, not a second one)

SCRIPT = Path(__file__).with_name("tuning_strips.py")
NAMES = ("rectilinear", "slanted", "stars")


def write(folder):
    return subprocess.run(
        [sys.executable, str(SCRIPT), str(folder)], capture_output=True, text=True
    )


def crosses(a, b, c, d):
    """True if segments ab and cd cross at a point inside both (not at a shared end)."""

    def side(p, q, r):
        v = (q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0])
        return (v > 0) - (v < 0)

    return side(a, b, c) * side(a, b, d) < 0 and side(c, d, a) * side(c, d, b) < 0


def simple(ring):
    """No two edges that do not share a vertex cross, and no vertex repeats."""
    n = len(ring)
    if len({tuple(p) for p in ring}) != n:
        return False
    edges = [(ring[i], ring[(i + 1) % n]) for i in range(n)]
    return not any(
        crosses(*edges[i], *edges[j])
        for i in range(n)
        for j in range(i + 2, n)
        if not (i == 0 and j == n - 1)
    )


class TuningStrips(unittest.TestCase):
    def test_every_run_writes_the_same_files(self):
        with tempfile.TemporaryDirectory() as a, tempfile.TemporaryDirectory() as b:
            for folder in (a, b):
                self.assertEqual(write(folder).returncode, 0)
            for name in NAMES:
                first = (Path(a) / f"{name}.json").read_bytes()
                self.assertEqual(first, (Path(b) / f"{name}.json").read_bytes(), name)

    def test_a_folder_that_holds_a_strip_is_left_as_it_was(self):
        with tempfile.TemporaryDirectory() as folder:
            mine = Path(folder) / "slanted.json"
            mine.write_text("a user's own file\n")
            run = write(folder)
            self.assertNotEqual(run.returncode, 0)
            self.assertIn("slanted.json", run.stderr)
            self.assertEqual(mine.read_text(), "a user's own file\n")
            self.assertEqual(sorted(p.name for p in Path(folder).iterdir()), ["slanted.json"])

    def test_the_parts_are_simple_rings_that_fit_across_their_strip(self):
        with tempfile.TemporaryDirectory() as folder:
            self.assertEqual(write(folder).returncode, 0)
            for name in NAMES:
                strip = json.loads((Path(folder) / f"{name}.json").read_text())
                width = strip["strip_height"]
                for item in strip["items"]:
                    ring = item["shape"]["data"][:-1]
                    self.assertEqual(item["shape"]["data"][0], item["shape"]["data"][-1])
                    self.assertTrue(all(isinstance(v, int) for p in ring for v in p), ring)
                    self.assertGreater(area(ring), 0, ring)
                    self.assertTrue(simple(ring), ring)
                    xs, ys = [p[0] for p in ring], [p[1] for p in ring]
                    # Across the strip is the instances' y; a quarter turn puts x across.
                    across = [max(ys) - min(ys)]
                    if 90.0 in item["allowed_orientations"]:
                        across.append(max(xs) - min(xs))
                    self.assertLessEqual(min(across), width, ring)

    def test_slanted_holds_parts_of_even_sizes_with_slanted_edges_among_them(self):
        with tempfile.TemporaryDirectory() as folder:
            self.assertEqual(write(folder).returncode, 0)
            strip = json.loads((Path(folder) / "slanted.json").read_text())
            rings = [item["shape"]["data"][:-1] for item in strip["items"]]
            self.assertEqual(len(rings), 25)
            slanted = 0
            for ring in rings:
                for axis in (0, 1):
                    size = max(p[axis] for p in ring) - min(p[axis] for p in ring)
                    self.assertIn(size, (6, 8, 10, 12), ring)
                n = len(ring)
                if any(
                    ring[i][0] != ring[(i + 1) % n][0] and ring[i][1] != ring[(i + 1) % n][1]
                    for i in range(n)
                ):
                    slanted += 1
            self.assertGreater(slanted, 0)
            self.assertLess(slanted, 25)


if __name__ == "__main__":
    unittest.main()
