#!/usr/bin/env python3
"""lidarseg against MRPT ICP on a few logs, in one screen (`./run.sh main`).

Each log is run once by lidarseg-odometry with both ICP baselines (keyframed like lidarseg,
and scan to scan), so the three methods see the same scans, the same prior and, for the
keyframed ICP, the same keyframe policy. Per log and method it prints the median, mean and
p99 time per scan, the speed-up (keyframed-ICP time / lidarseg time, same run, of the median
and of the mean: the recovery search runs on a minority of scans, which the median hides),
the accuracy where a reference exists (the paper's Table I against ground truth, or the
per-scan motion against a corrected log's poses), the final error and the lost scans.

  compare_with_icp.py --bin BUILD/apps --config default.ini --out DIR \
      --log NAME=PATH[,extra flag,...] ...
"""
import argparse
import json
import os
import subprocess
import sys
import time

METHODS = (("lidarseg", "lidarseg"), ("icp", "ICP kf"), ("icp-s2s", "ICP s2s"))


def run_odometry(bin_dir, config, log, out, extra):
    """Runs lidarseg-odometry with both baselines; returns its summary.json as a dict."""
    cmd = [os.path.join(bin_dir, "lidarseg-odometry"), "-q", "-c", config, "--baseline", "icp,icp-s2s",
           "-o", out] + extra + [log]
    with open(out + ".txt", "w") as stdout:
        rc = subprocess.call(cmd, stdout=stdout, stderr=subprocess.STDOUT)
    if rc != 0:
        sys.exit("lidarseg-odometry failed (%d) on %s: see %s.txt" % (rc, log, out))
    with open(os.path.join(out, "summary.json")) as f:
        return json.load(f)


def accuracy(method):
    """The method's accuracy as one cell, and the reference it was measured against."""
    errors = method.get("errors")
    if errors and "table1" in errors:
        t = errors["table1"]
        return ("Table I: edx %.2f mm, edy %.2f mm, edθ %.2f mrad" %
                (t["edx_m"] * 1e3, t["edy_m"] * 1e3, t["edtheta_rad"] * 1e3), "%.2f m" % errors["final_position_error_m"])
    rel = method.get("log_relations")
    if rel and rel.get("evaluated", 0) > 0:
        return ("per scan vs corrected poses: %.1f cm, %.2f° (median)" %
                (rel["translation_m"]["median"] * 100, rel["rotation_deg"]["median"]), "—")
    return ("no reference in this log", "—")


def rows_of(name, summary, out):
    """The lines printed for one log."""
    m = summary["methods"]
    lines = ["%s: %d scans, report %s" % (name, summary["frames"], os.path.relpath(os.path.join(out, "results.md")))]
    for key, label in METHODS:
        if key not in m:
            continue
        x = m[key]
        acc, final = accuracy(x)
        speed = "            "
        if key == "lidarseg" and "icp" in m and x["time_ms"]["mean"] > 0:
            speed = "%5.1f×/%4.1f×" % (summary.get("speedup_median", 0.0), m["icp"]["time_ms"]["mean"] / x["time_ms"]["mean"])
        if "lost" in x:
            lost = "%d%s" % (x["lost"], " (lost track)" if x.get("tracking") == "lost" else "")
        else:  # ICP does not know when it is lost; it says when it did not converge
            lost = "%d not converged" % x.get("status", {}).get("not_converged", 0)
        lines.append("  %-9s %8.0f %8.0f %8.0f  %s  %-52s %8s  %s" %
                     (label, x["time_ms"]["median"] * 1e3, x["time_ms"]["mean"] * 1e3, x["time_ms"]["p99"] * 1e3,
                      speed, acc, final, lost))
    return lines


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--bin", required=True, help="folder of the lidarseg tools")
    ap.add_argument("--config", required=True, help="configuration file (config/default.ini)")
    ap.add_argument("--out", required=True, help="output folder (one sub-folder per log)")
    ap.add_argument("--log", action="append", required=True, metavar="NAME=PATH[,FLAG,...]",
                    help="a log to run, with extra lidarseg-odometry flags")
    a = ap.parse_args()
    start = time.monotonic()
    print("lidarseg vs MRPT ICP: the same scans, the same prior, ICP kf keyframed like lidarseg")
    print("  %-9s %8s %8s %8s  %-12s  %-52s %8s  %s" %
          ("method", "med µs", "mean µs", "p99 µs", "speed", "accuracy", "final", "lost scans"))
    for spec in a.log:
        name, _, rest = spec.partition("=")
        path, *extra = rest.split(",")
        out = os.path.join(a.out, name.split(" ")[0])
        os.makedirs(a.out, exist_ok=True)
        summary = run_odometry(a.bin, a.config, path, out, [e for e in extra if e])
        print("\n".join(rows_of(name, summary, out)))
        sys.stdout.flush()
    print("speed: ICP kf time / lidarseg time per scan, median / mean, same run; final: position error at the "
          "end against ground truth. %.0f s in all." % (time.monotonic() - start))


if __name__ == "__main__":
    main()
