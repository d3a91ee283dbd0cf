#!/usr/bin/env python3
"""Unit tests of tests/benchmarks/paired.py (standard library only; run by CTest)."""
import math
import os
import random
import sys
import tempfile
import unittest

sys.dont_write_bytecode = True   # no __pycache__ in the source tree
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import paired  # noqa: E402


def write_tum(path, poses):
    with open(path, "w") as f:
        f.write("# timestamp x y z qx qy qz qw\n")
        for t, x, y, yaw in poses:
            f.write("%.6f %.9f %.9f 0 0 0 %.9f %.9f\n" % (t, x, y, math.sin(yaw / 2), math.cos(yaw / 2)))


def walk(steps, noise, seed):
    """A path turning slowly, and the same path with each step's translation perturbed."""
    rng = random.Random(seed)
    ref, est = [(0.0, 0.0, 0.0, 0.0)], [(0.0, 0.0, 0.0, 0.0)]
    for i in range(1, steps):
        t = 0.1 * i
        for poses, n in ((ref, 0.0), (est, noise)):
            _, x, y, yaw = poses[-1]
            dx, dy = 0.2 + rng.gauss(0.0, n), rng.gauss(0.0, n)
            poses.append((t, x + math.cos(yaw) * dx - math.sin(yaw) * dy,
                          y + math.sin(yaw) * dx + math.cos(yaw) * dy, yaw + 0.01))
    return ref, est


class Paired(unittest.TestCase):
    def test_a_perfect_estimate_has_zero_error_in_any_frame(self):
        ref, _ = walk(50, 0.0, 1)
        # The same motions from another origin and heading: every per-scan error is 0.
        c, s = math.cos(1.0), math.sin(1.0)
        moved = [(t, 3 + c * x - s * y, -2 + s * x + c * y, yaw + 1.0) for t, x, y, yaw in ref]
        errors = paired.scan_errors(moved, ref)
        self.assertEqual(len(errors), 49)
        self.assertLess(max(errors), 1e-6)

    def test_a_noisier_method_is_worse_and_equal_noise_ties(self):
        ref, good = walk(600, 0.005, 2)
        _, bad = walk(600, 0.03, 3)
        _, good2 = walk(600, 0.005, 4)
        with tempfile.TemporaryDirectory() as d:
            for name, poses in (("ref.tum", ref), ("good.tum", good), ("bad.tum", bad), ("good2.tum", good2)):
                write_tum(os.path.join(d, name), poses)
            c = paired.compare(d, "bad.tum", "good.tum", "ref.tum")
            self.assertEqual(c["scans"], 599)
            self.assertGreater(c["mean"][0], 3 * c["mean"][1])
            self.assertEqual(paired.verdict(c["mean_ci"]), "worse")
            self.assertEqual(paired.verdict(c["median_ci"]), "worse")
            self.assertEqual(paired.verdict(paired.compare(d, "good.tum", "bad.tum", "ref.tum")["mean_ci"]), "better")
            tie = paired.compare(d, "good.tum", "good2.tum", "ref.tum")
            self.assertEqual(paired.verdict(tie["mean_ci"]), "tie")
            self.assertIn("tie", paired.cell(tie))

    def test_correlated_errors_get_a_wider_interval_than_independent_ones(self):
        # The same spread of per-scan differences, independent or in runs of 40 equal values
        # (a corridor where one method is off for a while): resampling blocks must see that
        # the runs carry less information, resampling scans one by one would not.
        rng = random.Random(6)
        independent = [rng.gauss(0.0, 1.0) for _ in range(2000)]
        runs = [v for v in independent[:50] for _ in range(40)]
        zeros = [0.0] * 2000
        (ilo, ihi), _ = paired.block_bootstrap(independent, zeros)
        (rlo, rhi), _ = paired.block_bootstrap(runs, zeros)
        self.assertGreater(rhi - rlo, 2.0 * (ihi - ilo))
        with self.assertRaises(ValueError):
            paired.block_bootstrap([1.0], [2.0])

    def test_mismatched_files_are_refused_with_their_place(self):
        ref, est = walk(20, 0.01, 5)
        with self.assertRaises(ValueError):
            paired.scan_errors(est[:-1], ref)
        shifted = [(t + 0.5, x, y, yaw) for t, x, y, yaw in est]
        with self.assertRaisesRegex(ValueError, "scan 1: stamp"):
            paired.scan_errors(shifted, ref)
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "bad.tum")
            with open(path, "w") as f:
                f.write("0.0 0 0 0 0 0 0 1\n0.1 nan 0 0 0 0 0 1\n")
            with self.assertRaisesRegex(ValueError, "bad.tum:2: a field is not finite"):
                paired.read_tum(path)


if __name__ == "__main__":
    unittest.main()
