#!/usr/bin/env python3
"""Doors and corners on generated buildings (issue 18), with an honest split.

  buildings.py tune     [--seeds 1-20]    buildings the detector's rules may be tuned on
  buildings.py evaluate [--seeds 101-150] the held-out buildings: measure only

Both generate each building (lidarseg-simulate --building SEED, no camera) for each sensor,
run lidarseg-features against its truth (--matches-out) and aggregate recall and precision:
doors within --max-range-m (8 m) with both jambs visible (the truth's "resolvable": both
jambs, 0.5 m of wall beside each and the doorway seen with enough beams) and at most
--max-incidence-deg (60) from head-on; corners resolvable, matched within 0.2 m. Tables by
door width, recess depth, kind, incidence and distance, and the confusion between kinds.
`tune` refuses any seed outside 1-20: the held-out buildings (101-150) are never looked at
while tuning. Each run's counts go to OUT/<sensor>/b<seed>.json (the large files are
deleted); OUT/report.md and OUT/report.json hold the totals.
"""
import argparse
import csv
import json
import math
import os
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor

TUNING = (1, 20)
HELD_OUT = (101, 150)
DOOR_TYPES = ("door_open", "door_closed", "door_ajar")
CORNER_TYPES = ("corner_convex", "corner_concave")
KINDS = DOOR_TYPES + CORNER_TYPES
WIDTH_BINS = [(0.7, 0.9), (0.9, 1.2), (1.2, 1.6), (1.6, 2.01)]
RECESS_BINS = [(0.0, 0.02), (0.02, 0.05), (0.05, 0.1), (0.1, 0.2), (0.2, 0.31)]
INCIDENCE_BINS = [(0, 30), (30, 45), (45, 60), (60, 70), (70, 90.01)]
DISTANCE_BINS = [(0, 4), (4, 8), (8, 12), (12, 100)]


def parse_seeds(text):
    seeds = []
    for part in text.split(","):
        if "-" in part:
            lo, hi = part.split("-")
            seeds.extend(range(int(lo), int(hi) + 1))
        else:
            seeds.append(int(part))
    return seeds


def bin_name(bins, value):
    for lo, hi in bins:
        if lo <= value < hi:
            return "%g-%g" % (lo, min(hi, 2.0) if bins is WIDTH_BINS else hi)
    return None


def counter():
    return {"truths": 0, "found": 0, "right_kind": 0}


def add(table, key, found, right):
    c = table.setdefault(key, counter())
    c["truths"] += 1
    c["found"] += found
    c["right_kind"] += right


def score_run(matches_path, doors_path, max_range, max_incidence, min_step):
    """Counts of one run from its matches CSV and its door table."""
    doors = {}
    with open(doors_path) as f:
        for row in csv.DictReader(f):
            doors[int(row["id"])] = row
    out = {"doors": counter(), "doors_stepped": counter(), "corners": counter(), "by_width": {}, "by_recess": {}, "by_kind": {},
           "by_leaves": {}, "by_incidence": {}, "by_distance": {}, "confusion": {},
           "door_detections": 0, "door_detections_right": 0, "door_detections_8m": 0,
           "door_detections_8m_right": 0, "corner_detections": 0, "corner_detections_right": 0, "scans": 0}
    last_scan = None
    with open(matches_path) as f:
        for row in csv.DictReader(f):
            if row["scan"] != last_scan:
                out["scans"] += 1
                last_scan = row["scan"]
            x, y = float(row["x"]), float(row["y"])
            dist = math.hypot(x, y)
            if row["role"] == "detection":
                right = row["match"] != "none"
                if row["type"] in DOOR_TYPES:
                    out["door_detections"] += 1
                    out["door_detections_right"] += right
                    if dist <= max_range:
                        out["door_detections_8m"] += 1
                        out["door_detections_8m_right"] += right
                else:
                    out["corner_detections"] += 1
                    out["corner_detections_right"] += right
                continue
            if row["resolvable"] != "1":
                continue
            found = row["match"] != "none"
            right = row["match"] in (row["type"], row["seen_as"])
            if row["type"] in CORNER_TYPES:
                c = out["corners"]
                c["truths"] += 1
                c["found"] += found
                c["right_kind"] += right
                conf = out["confusion"].setdefault(row["seen_as"], {})
                conf[row["match"]] = conf.get(row["match"], 0) + 1
                continue
            theta = float(row["theta"])
            cos_inc = abs(math.cos(theta) * x + math.sin(theta) * y) / max(dist, 1e-9)
            incidence = math.degrees(math.acos(min(1.0, cos_inc)))
            if dist <= max_range:
                add(out["by_incidence"], bin_name(INCIDENCE_BINS, incidence), found, right)
            if incidence <= max_incidence:
                add(out["by_distance"], bin_name(DISTANCE_BINS, dist), found, right)
            if dist > max_range or incidence > max_incidence:
                continue
            door = doors[int(row["id"])]
            c = out["doors"]
            c["truths"] += 1
            c["found"] += found
            c["right_kind"] += right
            if not (door["kind"] == "closed" and float(door["recess"]) < min_step):
                c = out["doors_stepped"]
                c["truths"] += 1
                c["found"] += found
                c["right_kind"] += right
            add(out["by_width"], bin_name(WIDTH_BINS, float(door["width"])), found, right)
            if door["kind"] == "closed":
                add(out["by_recess"], "closed " + bin_name(RECESS_BINS, float(door["recess"])), found, right)
            elif door["kind"] == "ajar":
                add(out["by_recess"], "ajar (hinge) " + bin_name(RECESS_BINS, float(door["recess"])), found, right)
            add(out["by_kind"], row["seen_as"], found, right)
            add(out["by_leaves"], "double" if door["double"] == "1" else "single", found, right)
            conf = out["confusion"].setdefault(row["seen_as"], {})
            conf[row["match"]] = conf.get(row["match"], 0) + 1
    return out


def merge(total, part):
    for k, v in part.items():
        if isinstance(v, dict):
            merge(total.setdefault(k, {}), v)
        else:
            total[k] = total.get(k, 0) + v


def run_one(args, sensor, seed):
    folder = os.path.join(args.out, sensor)
    result = os.path.join(folder, "b%d.json" % seed)
    if args.resume and os.path.exists(result):
        with open(result) as f:
            return json.load(f)
    os.makedirs(folder, exist_ok=True)
    prefix = os.path.join(folder, "b%d" % seed)
    sim = [os.path.join(args.bin, "lidarseg-simulate"), "--building", str(seed), "--sensor-model", sensor,
           "--seed", str(seed), "--camera-every", "0", "-o", prefix]
    feat = [os.path.join(args.bin, "lidarseg-features"), prefix + ".rawlog", "--gt", prefix + ".features.csv",
            "--matches-out", prefix + ".matches.csv"]
    if args.config:
        feat += ["-c", args.config]
    for cmd in (sim, feat):
        done = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
        if done.returncode != 0:
            sys.exit("failed (%d): %s\n%s" % (done.returncode, " ".join(cmd), done.stderr))
    counts = score_run(prefix + ".matches.csv", prefix + ".doors.csv", args.max_range_m, args.max_incidence_deg,
                       args.min_step_m)
    counts["seed"] = seed
    for ext in (".rawlog", ".matches.csv", ".features.csv", ".gt.tum", ".odom.tum", ".rois.csv"):
        if not args.keep and os.path.exists(prefix + ext):
            os.remove(prefix + ext)
    with open(result + ".tmp", "w") as f:
        json.dump(counts, f)
    os.replace(result + ".tmp", result)
    return counts


def ratio(a, b):
    return "%.3f" % (a / b) if b else "–"


def table(lines, title, rows):
    lines.append("| %s | true | found | recall | right kind | recall (kind) |" % title)
    lines.append("|---|---:|---:|---:|---:|---:|")
    for name, c in rows:
        lines.append("| %s | %d | %d | %s | %d | %s |" % (name, c["truths"], c["found"], ratio(c["found"], c["truths"]),
                                                          c["right_kind"], ratio(c["right_kind"], c["truths"])))
    lines.append("")


def report(total, args, sensors_totals):
    lines = ["# Doors and corners on generated buildings (%s, seeds %s)" % (args.command, args.seeds), ""]
    lines.append("Doors counted: resolvable (both jambs), within %g m, at most %g deg from head-on; corners: "
                 "resolvable; matched within 0.2 m. Found = matched by a detection of the same family; "
                 "right kind = its type (or what it is seen as)." % (args.max_range_m, args.max_incidence_deg))
    lines.append("")
    lines.append("| sensor | scans | door recall | door recall (kind) | door recall, leaves recessed ≥ %g m | "
                 "door precision | door precision (≤ %g m) | corner recall | corner precision |"
                 % (args.min_step_m, args.max_range_m))
    lines.append("|---|---:|---:|---:|---:|---:|---:|---:|---:|")
    for sensor, t in sensors_totals + [("**all**", total)]:
        d, c, ds = t["doors"], t["corners"], t["doors_stepped"]
        lines.append("| %s | %d | %s (%d/%d) | %s | %s (%d/%d) | %s (%d/%d) | %s | %s (%d/%d) | %s (%d/%d) |" % (
            sensor, t["scans"], ratio(d["found"], d["truths"]), d["found"], d["truths"],
            ratio(d["right_kind"], d["truths"]), ratio(ds["found"], ds["truths"]), ds["found"], ds["truths"],
            ratio(t["door_detections_right"], t["door_detections"]), t["door_detections_right"], t["door_detections"],
            ratio(t["door_detections_8m_right"], t["door_detections_8m"]),
            ratio(c["found"], c["truths"]), c["found"], c["truths"],
            ratio(t["corner_detections_right"], t["corner_detections"]), t["corner_detections_right"],
            t["corner_detections"]))
    lines.append("")
    for sensor, t in sensors_totals:
        lines.append("## %s" % sensor)
        lines.append("")
        table(lines, "door width (m)", sorted(t["by_width"].items()))
        table(lines, "door, recess of the leaf / hinges (m)", sorted(t["by_recess"].items()))
        table(lines, "door seen as", sorted(t["by_kind"].items()))
        table(lines, "leaves", sorted(t["by_leaves"].items()))
        table(lines, "incidence (deg), doors ≤ %g m" % args.max_range_m,
              sorted(t["by_incidence"].items(), key=lambda kv: float(kv[0].split("-")[0])))
        table(lines, "distance (m), doors ≤ %g deg" % args.max_incidence_deg,
              sorted(t["by_distance"].items(), key=lambda kv: float(kv[0].split("-")[0])))
        lines.append("Confusion (rows: true kind as the scan can show it; columns: detected; counted doors and "
                     "resolvable corners):")
        lines.append("")
        cols = list(KINDS) + ["none"]
        lines.append("| | " + " | ".join(cols) + " |")
        lines.append("|---|" + "---:|" * len(cols))
        for k in KINDS:
            row = t["confusion"].get(k, {})
            lines.append("| %s | %s |" % (k, " | ".join(str(row.get(c, 0)) for c in cols)))
        lines.append("")
    return "\n".join(lines) + "\n"


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("command", choices=["tune", "evaluate"])
    ap.add_argument("--seeds", help="e.g. 1-20 or 101-150 or 3,5,7 (default: the command's set)")
    ap.add_argument("--sensors", default="lms100,utm30lx")
    ap.add_argument("--bin", default="build/release/apps", help="folder of lidarseg-simulate and lidarseg-features")
    ap.add_argument("-c", "--config", default="", help="configuration for lidarseg-features")
    ap.add_argument("--out", required=True)
    ap.add_argument("-j", "--jobs", type=int, default=1)
    ap.add_argument("--max-range-m", type=float, default=8.0)
    ap.add_argument("--max-incidence-deg", type=float, default=60.0)
    ap.add_argument("--keep", action="store_true", help="keep each run's rawlog and CSV files")
    ap.add_argument("--resume", action="store_true", help="reuse the runs already scored in OUT")
    ap.add_argument("--min-step-m", type=float, default=0.02,
                    help="the second door figure leaves out closed leaves recessed less than this (no jamb to see)")
    args = ap.parse_args()
    allowed = TUNING if args.command == "tune" else HELD_OUT
    args.seeds = args.seeds or "%d-%d" % allowed
    seeds = parse_seeds(args.seeds)
    bad = [s for s in seeds if not allowed[0] <= s <= allowed[1]]
    if bad:
        what = "held out for evaluation, never used while tuning" if args.command == "tune" else "not held out"
        sys.exit("buildings.py %s: seeds %s refused: %s only takes seeds %d-%d (%s)" % (
            args.command, ",".join(map(str, bad[:10])), args.command, allowed[0], allowed[1],
            "101-150 are " + what if args.command == "tune" else "the others are " + what))
    sensors = args.sensors.split(",")
    jobs = [(s, seed) for s in sensors for seed in seeds]
    with ThreadPoolExecutor(max_workers=max(1, args.jobs)) as pool:
        results = list(pool.map(lambda job: run_one(args, *job), jobs))
    total, per_sensor = {}, []
    for sensor in sensors:
        t = {}
        for (s, _), r in zip(jobs, results):
            if s == sensor:
                merge(t, {k: v for k, v in r.items() if k != "seed"})
        per_sensor.append((sensor, t))
        merge(total, t)
    text = report(total, args, per_sensor)
    with open(os.path.join(args.out, "report.md"), "w") as f:
        f.write(text)
    with open(os.path.join(args.out, "report.json"), "w") as f:
        json.dump({"command": args.command, "seeds": args.seeds, "total": total, "sensors": dict(per_sensor)}, f,
                  indent=1, sort_keys=True)
    print(text)


if __name__ == "__main__":
    main()
