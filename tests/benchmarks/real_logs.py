#!/usr/bin/env python3
"""Runs lidarseg-odometry with both MRPT ICP baselines on every real log and prints one table.

Two groups (docs/results.md):
  * the Radish corrected logs with their wheel odometry as the prior, evaluated per scan
    against the logs' corrected poses (--use-odometry --log-reference);
  * dense logs with a constant-velocity prior (no odometry): intel.rawlog, freiburg-079
    (evaluated against its corrected poses), MRPT's Telecom Faculty and localization demo.
Each run writes OUT/<group>/<log>/ (summary.json, results.md, trajectories) and OUT/table.md.
"""
import argparse
import glob
import json
import os
import sys

from compare_with_icp import run_odometry
import paired


def run(bin_dir, config, log, out, extra):
    """lidarseg-odometry with both baselines, no pictures; its summary.json."""
    return run_odometry(bin_dir, config, log, out, ["--no-plots"] + extra)


def cell(method, key):
    rel = method.get("log_relations")
    if not rel:
        return "—"
    t = rel["translation_m"]
    if key == "t":
        return "%.1f / %.1f" % (t["mean"] * 100, t["median"] * 100)
    return "%.2f" % rel["rotation_deg"]["mean"]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--bin", required=True)
    ap.add_argument("--config", required=True)
    ap.add_argument("--shared", required=True)
    ap.add_argument("--mrpt", required=True)
    ap.add_argument("--out", required=True)
    a = ap.parse_args()
    runs = []
    for log in sorted(glob.glob(os.path.join(a.shared, "radish-corrected", "*.log.gz"))):
        runs.append(("odometry", log, ["--use-odometry", "--log-reference"]))
    dense = [(os.path.join(a.shared, "intel-mrpt", "intel.rawlog"), []),
             (os.path.join(a.shared, "radish-corrected", "freiburg-079-corrected.log.gz"), ["--log-reference"]),
             (os.path.join(a.mrpt, "2006-01ENE-21-SENA_Telecom Faculty_one_loop_only.rawlog"), []),
             (os.path.join(a.mrpt, "localization_demo.rawlog"), [])]
    for log, extra in dense:
        if os.path.exists(log):
            runs.append(("constant-velocity", log, extra))
    rows = []
    header = ("| log | prior | scans | lidarseg trans. mean / median (cm) | ICP kf | ICP s2s | "
              "lidarseg rot. mean (deg) | ICP kf | ICP s2s | lost | median µs lidarseg / ICP kf | speed-up | "
              "mean µs lidarseg / ICP kf | mean speed-up | lidarseg − ICP kf per scan (cm): Δ mean [95 % CI]; "
              "Δ median [95 % CI] |\n"
              "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|")
    print(header)
    for group, log, extra in runs:
        name = os.path.basename(log).split(".")[0].replace(" ", "_")
        out = os.path.join(a.out, group, name)
        os.makedirs(os.path.dirname(out), exist_ok=True)
        print("[real] %s (%s)" % (name, group), file=sys.stderr)
        s = run(a.bin, a.config, log, out, extra)
        m = s["methods"]
        l, k, c = m["lidarseg"], m["icp"], m["icp-s2s"]
        lost = "%d (%.1f %%)%s" % (l["lost"], 100.0 * l["lost"] / max(1, s["frames"]),
                                  " **lost**" if l["tracking"] == "lost" else "")
        # The mean as well as the median: the recovery search runs on a minority of scans, so
        # the median hides it, and a user processing whole logs pays the mean.
        mean_ratio = k["time_ms"]["mean"] / l["time_ms"]["mean"] if l["time_ms"]["mean"] > 0 else 0.0
        # Scan by scan against keyframed ICP, with a block-bootstrap interval: a difference
        # whose interval holds 0 is a tie that one run cannot settle.
        try:
            diff = paired.cell(paired.compare(out)) if l.get("log_relations") else "—"
        except (ValueError, ArithmeticError) as e:  # too few scans, files that do not pair
            print("[real] %s: no paired comparison: %s" % (name, e), file=sys.stderr)
            diff = "—"
        row = "| %s | %s | %d | %s | %s | %s | %s | %s | %s | %s | %.0f / %.0f | %.1f× | %.0f / %.0f | %.1f× | %s |" % (
            name, group, s["frames"], cell(l, "t"), cell(k, "t"), cell(c, "t"), cell(l, "r"), cell(k, "r"),
            cell(c, "r"), lost, l["time_ms"]["median"] * 1e3, k["time_ms"]["median"] * 1e3,
            s.get("speedup_median", 0.0), l["time_ms"]["mean"] * 1e3, k["time_ms"]["mean"] * 1e3, mean_ratio, diff)
        print(row)
        sys.stdout.flush()
        rows.append(row)
    with open(os.path.join(a.out, "table.md"), "w") as f:
        f.write(header + "\n" + "\n".join(rows) + "\n")


if __name__ == "__main__":
    main()
