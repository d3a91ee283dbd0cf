#!/usr/bin/env python3
"""Paired comparison of two odometry runs of one log, scan by scan (docs/results.md).

Both trajectories and the reference are TUM files with one pose per scan (lidarseg-odometry's
lidarseg.tum, icp.tum and log-poses.tum). Each scan's error is that of its motion since the
previous scan against the reference's (translation, m), as lidarseg-odometry's
"log_relations". The two methods' errors are paired by scan, and the difference of their means
(and of their medians) gets a 95 % interval from a moving-block bootstrap: consecutive scans'
errors are correlated (a corridor, a keyframe), so blocks of scans are resampled, not scans.
A difference whose interval holds 0 is a tie: one run cannot tell the two methods apart there.

Usage: paired.py RUN_DIR [A B]   (default A = lidarseg.tum, B = icp.tum; prints one line)
"""
import math
import os
import random
import statistics
import sys


def read_tum(path):
    """(stamp, x, y, yaw) per line of a TUM file; comments skipped."""
    poses = []
    with open(path) as f:
        for n, line in enumerate(f, 1):
            if not line.strip() or line.startswith("#"):
                continue
            v = line.split()
            if len(v) != 8:
                raise ValueError("%s:%d: a TUM line has 8 fields, this one %d" % (path, n, len(v)))
            t, x, y, qz, qw = float(v[0]), float(v[1]), float(v[2]), float(v[6]), float(v[7])
            if not all(math.isfinite(u) for u in (t, x, y, qz, qw)):
                raise ValueError("%s:%d: a field is not finite" % (path, n))
            poses.append((t, x, y, 2.0 * math.atan2(qz, qw)))
    return poses


def motion(a, b):
    """b relative to a: (dx, dy) in a's frame."""
    dx, dy = b[1] - a[1], b[2] - a[2]
    c, s = math.cos(a[3]), math.sin(a[3])
    return c * dx + s * dy, -s * dx + c * dy


def scan_errors(estimate, reference):
    """Per-scan translation error of the motion since the previous scan (m)."""
    if len(estimate) != len(reference):
        raise ValueError("%d poses against %d reference poses" % (len(estimate), len(reference)))
    errors = []
    for i in range(1, len(estimate)):
        if abs(estimate[i][0] - reference[i][0]) > 1e-3:
            raise ValueError("scan %d: stamp %.6f against the reference's %.6f" % (i, estimate[i][0], reference[i][0]))
        e, r = motion(estimate[i - 1], estimate[i]), motion(reference[i - 1], reference[i])
        errors.append(math.hypot(e[0] - r[0], e[1] - r[1]))
    return errors


def block_bootstrap(a, b, resamples=1000, block=20, seed=1):
    """95 % intervals of mean(a) - mean(b) and median(a) - median(b), a and b paired by index."""
    n = len(a)
    if n < 2 or len(b) != n:
        raise ValueError("a paired comparison needs two equal series of 2 scans or more (%d, %d)" % (n, len(b)))
    if n < 2 * block:
        block = max(1, n // 4)
    starts = n - block + 1
    rng = random.Random(seed)
    mean_d, median_d = [], []
    for _ in range(resamples):
        ia = []
        while len(ia) < n:
            s = rng.randrange(starts)
            ia.extend(range(s, s + block))
        ia = ia[:n]
        xa = [a[i] for i in ia]
        xb = [b[i] for i in ia]
        mean_d.append((sum(xa) - sum(xb)) / n)
        median_d.append(statistics.median(xa) - statistics.median(xb))
    mean_d.sort()
    median_d.sort()
    lo, hi = int(0.025 * resamples), int(0.975 * resamples) - 1
    return (mean_d[lo], mean_d[hi]), (median_d[lo], median_d[hi])


def compare(run_dir, a="lidarseg.tum", b="icp.tum", reference="log-poses.tum"):
    """The paired comparison of two trajectories of one run: a dict of figures (m)."""
    ref = read_tum(os.path.join(run_dir, reference))
    ea = scan_errors(read_tum(os.path.join(run_dir, a)), ref)
    eb = scan_errors(read_tum(os.path.join(run_dir, b)), ref)
    (mlo, mhi), (dlo, dhi) = block_bootstrap(ea, eb)
    return {"scans": len(ea),
            "mean": (statistics.fmean(ea), statistics.fmean(eb)), "mean_ci": (mlo, mhi),
            "median": (statistics.median(ea), statistics.median(eb)), "median_ci": (dlo, dhi)}


def verdict(ci):
    """'better' (A below B), 'worse' or 'tie' from a difference's interval."""
    return "better" if ci[1] < 0 else "worse" if ci[0] > 0 else "tie"


def cell(c):
    """'Δ mean [lo, hi] verdict; Δ median [lo, hi] verdict' in cm."""
    dm = (c["mean"][0] - c["mean"][1]) * 100
    dd = (c["median"][0] - c["median"][1]) * 100
    return "%+.2f [%+.2f, %+.2f] %s; %+.2f [%+.2f, %+.2f] %s" % (
        dm, c["mean_ci"][0] * 100, c["mean_ci"][1] * 100, verdict(c["mean_ci"]),
        dd, c["median_ci"][0] * 100, c["median_ci"][1] * 100, verdict(c["median_ci"]))


if __name__ == "__main__":
    if len(sys.argv) not in (2, 4):
        sys.exit(__doc__)
    args = sys.argv[2:] if len(sys.argv) == 4 else []
    print(cell(compare(sys.argv[1], *args)))
