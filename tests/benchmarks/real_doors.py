#!/usr/bin/env python3
"""Doors on real scans against hand labels (issue 18, "Real scans").

Subcommands (python3 standard library only; pictures by gnuplot, as every project chart):

  select   LOG --count K [--phase F] [--exclude LABELS_DIR]
                                  the scans to label, chosen before looking: indices
                                  round((k + F) * N / K), k < K, less those already labelled
  render   LOG --scans I,J,.. --out DIR [--zoom X,Y,HALF]
                                  one picture per scan of its raw points only (no detector
                                  output) on a metric grid, sensor frame: x forward, y left
  evaluate --labels DIR --shared DIR --bin DIR --out DIR [--figures N]
                                  runs lidarseg-features on every labelled log, matches its
                                  doors to the labels (lidarseg's rule: one to one, right
                                  kind first, then nearest, centres within --tol) and
                                  reports recall and precision; draws up to N failures of
                                  each kind, zoomed; exit 77 when a log is missing
  check    --labels DIR [--shared DIR]
                                  parses every labels file and checks its rules (and the
                                  stamps against the logs)

Tests: test_real_doors.py (CTest real_doors.*).
Labels: datasets/labels/real-doors/<log>.csv (README.md there says how they were made).
The logs themselves are never copied: a label names its log, scan index and stamp.
"""
import argparse
import csv
import glob
import gzip
import json
import math
import os
import shutil
import subprocess
import sys
import tempfile

LASER_TYPES = ("FLASER", "RLASER", "ROBOTLASER1")
LABEL_COLUMNS = ["log", "scan", "stamp", "kind", "x1", "y1", "x2", "y2", "ambiguous", "note"]
KINDS = ("none", "open", "closed", "ajar", "door")
DEFAULT_TOL_M = 0.3     # door centre to label centre
DEFAULT_RANGE_M = 8.0   # doors are labelled (and detections scored) within this range


# ---------------------------------------------------------------------------- reading
def is_sick_error(r):
    """The same codes as CarmenLogReader: SICK's 'no return' values."""
    return r >= 81.83 or 32.763 <= r <= 32.767


def read_carmen(path, max_range_default=50.0):
    """The laser scans of a CARMEN log as lidarseg's CarmenLogReader numbers them.

    Only FLASER/RLASER lines (the corrected Radish logs have nothing else); the first laser
    type that parses decides the type. Returns a list of dicts: index, stamp, ranges,
    start, res, max_range (radians, metres; a beam is valid when 0 < r < max_range)."""
    opener = gzip.open if path.endswith(".gz") else open
    params = {}
    scans = []
    laser_type = None
    with opener(path, "rt", errors="replace") as f:
        for line in f:
            fl = line.split()
            if not fl or fl[0].startswith("#"):
                continue
            if fl[0] == "PARAM" and len(fl) >= 3:
                params[fl[1]] = fl[2]
                continue
            if fl[0] not in ("FLASER", "RLASER"):
                continue
            if laser_type is not None and fl[0] != laser_type:
                continue
            try:
                n = int(fl[1])
                if len(fl) != n + 11 or n < 2:
                    continue
                ranges = [float(v) for v in fl[2:2 + n]]
                stamp = float(fl[n + 8])
            except ValueError:
                continue
            side = "front" if fl[0] == "FLASER" else "rear"

            def param(name, fallback):
                try:
                    v = float(params.get(name, ""))
                    return v if math.isfinite(v) else fallback
                except ValueError:
                    return fallback
            fov = param("laser_%s_laser_fov" % side, 180.0)
            res = param("laser_%s_laser_resolution" % side, 0.0)
            if not res > 0.0:
                res = fov / (n - 1) if n % 2 == 1 else fov / n
            max_range = param("robot_%s_laser_max" % side, 0.0)
            if not max_range > 0.0:
                max_range = param("laser_%s_laser_max_range" % side, 0.0)
            if not max_range > 0.0:
                max_range = max_range_default
            laser_type = laser_type or fl[0]
            scans.append({"index": len(scans), "stamp": stamp,
                          "ranges": [math.inf if is_sick_error(r) else r for r in ranges],
                          "start": math.radians(-0.5 * fov), "res": math.radians(res),
                          "max_range": max_range})
    return scans


def scan_points(scan):
    """Valid beams as (x, y) in the sensor frame (the corrected logs' laser offset is 0)."""
    pts = []
    for i, r in enumerate(scan["ranges"]):
        if 0.0 < r < scan["max_range"]:
            a = scan["start"] + i * scan["res"]
            pts.append((r * math.cos(a), r * math.sin(a)))
    return pts


# ---------------------------------------------------------------------------- labels
def read_labels(path):
    """Rows of one labels file, checked. Returns {(log, scan): [row, ...]}."""
    out = {}
    with open(path, newline="") as f:
        rows = list(csv.DictReader(line for line in f if not line.startswith("#")))
    for n, row in enumerate(rows, start=2):
        where = "%s: row %d" % (path, n)
        missing = [c for c in LABEL_COLUMNS if c not in row or row[c] is None]
        if missing:
            raise ValueError("%s: missing column(s) %s" % (where, ",".join(missing)))
        kind = row["kind"].strip()
        if kind not in KINDS:
            raise ValueError("%s: kind '%s' is not one of %s" % (where, kind, ",".join(KINDS)))
        if row["ambiguous"].strip() not in ("0", "1"):
            raise ValueError("%s: ambiguous must be 0 or 1" % where)
        lab = {"log": row["log"].strip(), "scan": int(row["scan"]), "stamp": float(row["stamp"]),
               "kind": kind, "ambiguous": row["ambiguous"].strip() == "1", "note": row["note"]}
        if kind != "none":
            try:
                lab["j1"] = (float(row["x1"]), float(row["y1"]))
                lab["j2"] = (float(row["x2"]), float(row["y2"]))
            except ValueError:
                raise ValueError("%s: a door needs both jambs x1,y1,x2,y2" % where)
            w = math.dist(lab["j1"], lab["j2"])
            if not lab["ambiguous"] and not 0.5 <= w <= 2.4:
                raise ValueError("%s: door %.2f m wide (labelled doors are 0.6-2.2 m, read to 0.1 m)"
                                 % (where, w))
            lab["centre"] = ((lab["j1"][0] + lab["j2"][0]) / 2, (lab["j1"][1] + lab["j2"][1]) / 2)
            lab["width"] = w
        out.setdefault((lab["log"], lab["scan"]), []).append(lab)
    for key, labs in out.items():
        if any(l["kind"] == "none" for l in labs) and len(labs) > 1:
            raise ValueError("%s: scan %d of %s is marked 'none' and also has doors"
                             % (path, key[1], key[0]))
    return out


def read_all_labels(labels_dir):
    files = sorted(glob.glob(os.path.join(labels_dir, "*.csv")))
    if not files:
        raise ValueError("no labels file (*.csv) in " + labels_dir)
    labels = {}
    for p in files:
        for key, labs in read_labels(p).items():
            if key in labels:
                raise ValueError("%s: scan %d of %s labelled twice" % (p, key[1], key[0]))
            labels[key] = labs
    return labels


# ---------------------------------------------------------------------------- matching
def match_doors(labels, detections, tol):
    """One-to-one matching of door centres within tol, the rule of lidarseg-features --gt
    (FeatureEvaluation: same family within the gate; pairs of the right kind first, then
    nearest first). The right kind: a label `open` and a `door_open`, and so on.

    labels: [{'centre': (x, y), ...}], detections: [{'x':, 'y':, ...}]. Ambiguous labels take
    part (a detection on one is neither right nor wrong). Returns (label_match, det_match):
    for each label the index of its detection or -1, for each detection its label's or -1."""
    pairs = []
    for i, lab in enumerate(labels):
        for j, det in enumerate(detections):
            d = math.dist(lab["centre"], (det["x"], det["y"]))
            if d <= tol:
                pairs.append((det.get("type") != "door_" + lab["kind"], d, i, j))
    pairs.sort()
    lm = [-1] * len(labels)
    dm = [-1] * len(detections)
    for _, d, i, j in pairs:
        if lm[i] < 0 and dm[j] < 0:
            lm[i] = j
            dm[j] = i
    return lm, dm


def wilson(k, n, z=1.96):
    """95 % Wilson score interval of a proportion k / n (small counts)."""
    if n == 0:
        return (float("nan"), float("nan"))
    p = k / n
    d = 1 + z * z / n
    c = (p + z * z / (2 * n)) / d
    h = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / d
    return (max(0.0, c - h), min(1.0, c + h))


def score(labels, detections_by_scan, tol, max_range):
    """Counts over the labelled scans. A detection counts towards precision when its centre
    is within max_range (the labelled zone); one matched to an ambiguous label is left out."""
    s = {"scans": 0, "scans_with_doors": 0, "labels": 0, "ambiguous": 0, "found": 0,
         "detections": 0, "true_detections": 0, "false_detections": 0, "beyond_range": 0,
         "on_ambiguous": 0, "missed": [], "false": [], "hits": []}
    for key in sorted(labels):
        labs = [l for l in labels[key] if l["kind"] != "none"]
        dets = detections_by_scan.get(key, [])
        s["scans"] += 1
        if any(not l["ambiguous"] for l in labs):
            s["scans_with_doors"] += 1
        lm, dm = match_doors(labs, dets, tol)
        for i, lab in enumerate(labs):
            if lab["ambiguous"]:
                s["ambiguous"] += 1
                continue
            s["labels"] += 1
            if lm[i] >= 0:
                s["found"] += 1
                s["hits"].append((key, lab, dets[lm[i]]))
            else:
                s["missed"].append((key, lab))
        for j, det in enumerate(dets):
            if math.hypot(det["x"], det["y"]) > max_range:
                s["beyond_range"] += 1
                continue
            if dm[j] >= 0 and labs[dm[j]]["ambiguous"]:
                s["on_ambiguous"] += 1
                continue
            s["detections"] += 1
            if dm[j] >= 0:
                s["true_detections"] += 1
            else:
                s["false_detections"] += 1
                s["false"].append((key, det))
    s["recall"] = s["found"] / s["labels"] if s["labels"] else float("nan")
    s["precision"] = s["true_detections"] / s["detections"] if s["detections"] else float("nan")
    return s


# ---------------------------------------------------------------------------- pictures
def gnuplot(script, cwd):
    gp = shutil.which("gnuplot")
    if not gp:
        raise RuntimeError("gnuplot not found (./run.sh deps installs gnuplot-nox)")
    with open(os.path.join(cwd, "plot.gp"), "w") as f:
        f.write(script)
    subprocess.run([gp, "plot.gp"], cwd=cwd, check=True, stdin=subprocess.DEVNULL)


def draw_scan(scan, png, title, view=None, labels=(), detections=(), size=(1700, 1000)):
    """Raw points (black) on a 1 m grid with 0.25 m minor lines, drawn with the sensor's x
    (forward) up and its y (left) to the left; optional hand labels (green: jambs joined,
    ambiguous dashed orange) and detections (red: jambs joined, centre circled).
    view: (xmin, xmax, ymin, ymax) in the sensor frame."""
    if view is None:
        view = (-1.0, DEFAULT_RANGE_M + 0.5, -(DEFAULT_RANGE_M + 0.5), DEFAULT_RANGE_M + 0.5)
    tmp = tempfile.mkdtemp(prefix="real_doors_")
    try:
        with open(os.path.join(tmp, "pts.dat"), "w") as f:
            for x, y in scan_points(scan):
                f.write("%.4f %.4f\n" % (x, y))
        with open(os.path.join(tmp, "lab.dat"), "w") as f:
            for lab in labels:
                if not lab["ambiguous"]:
                    f.write("%.3f %.3f\n%.3f %.3f\n\n" % (lab["j1"] + lab["j2"]))
            f.write("\n")
        with open(os.path.join(tmp, "amb.dat"), "w") as f:
            for lab in labels:
                if lab["ambiguous"]:
                    f.write("%.3f %.3f\n%.3f %.3f\n\n" % (lab["j1"] + lab["j2"]))
            f.write("\n")
        with open(os.path.join(tmp, "det.dat"), "w") as f:
            for d in detections:
                c, s = math.cos(d["theta"]), math.sin(d["theta"])
                tx, ty = -s, c   # along the wall
                h = d["width"] / 2
                f.write("%.3f %.3f\n%.3f %.3f\n\n" % (d["x"] - tx * h, d["y"] - ty * h,
                                                      d["x"] + tx * h, d["y"] + ty * h))
            f.write("\n")
        with open(os.path.join(tmp, "detc.dat"), "w") as f:
            for d in detections:
                f.write("%.3f %.3f\n" % (d["x"], d["y"]))
            f.write("\n")
        span = max(view[1] - view[0], view[3] - view[2])
        major = 1.0 if span > 4 else 0.5
        minor = 4 if span > 4 else 5
        plots = ["'pts.dat' using 2:1 with points pt 7 ps 0.45 lc rgb 'black' title 'scan points'"]
        if any(not l["ambiguous"] for l in labels):
            plots.append("'lab.dat' using 2:1 with linespoints lw 3 pt 6 ps 1.5 lc rgb '#00a000' title 'hand label'")
        if any(l["ambiguous"] for l in labels):
            plots.append("'amb.dat' using 2:1 with linespoints lw 2 dt 2 pt 6 ps 1.5 lc rgb '#ff8c00' title 'ambiguous'")
        if detections:
            plots.append("'det.dat' using 2:1 with lines lw 2 lc rgb 'red' title 'detected door'")
            plots.append("'detc.dat' using 2:1 with points pt 6 ps 2.5 lw 2 lc rgb 'red' notitle")
        plots.append("'-' using 2:1 with points pt 2 ps 2.5 lw 3 lc rgb 'blue' title 'sensor (x forward)'")
        script = """
set terminal pngcairo size %d,%d font 'DejaVu Sans,11'
set output '%s'
set title "%s" noenhanced
set size ratio -1
set yrange [%g:%g]
set xrange [%g:%g]
set xtics %g
set ytics %g
set mxtics %d
set mytics %d
set grid xtics ytics mxtics mytics lc rgb '#909090' lw 1, lc rgb '#d0d0d0' lw 1
set xlabel 'y (m, left of the sensor; axis reversed)'
set ylabel 'x (m, forward)'
set key bottom left opaque box
set arrow from 0,0 to 0,0.5 lc rgb 'blue' lw 2
plot %s
0 0
e
""" % (size[0], size[1], os.path.abspath(png), title.replace('"', "'"), view[0], view[1], view[3],
            view[2], major, major, minor, minor, ", ".join(plots))
        gnuplot(script, tmp)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


# ---------------------------------------------------------------------------- commands
def log_name(path):
    base = os.path.basename(path)
    for ext in (".log.gz", ".clf.gz", ".gz", ".log", ".clf"):
        if base.endswith(ext):
            return base[:-len(ext)]
    return base


def cmd_select(a):
    scans = read_carmen(a.log)
    n = len(scans)
    idx = sorted({int(round((k + a.phase) * n / a.count)) for k in range(a.count)})
    taken = set()
    if a.exclude:
        taken = {k[1] for k in read_all_labels(a.exclude) if k[0] == log_name(a.log)}
    print(",".join(str(i) for i in idx if i < n and i not in taken))


def cmd_render(a):
    scans = read_carmen(a.log)
    os.makedirs(a.out, exist_ok=True)
    name = log_name(a.log)
    for i in (int(v) for v in a.scans.split(",")):
        s = scans[i]
        view = None
        suffix = ""
        if a.zoom:
            zx, zy, h = (float(v) for v in a.zoom.split(","))
            view = (zx - h, zx + h, zy - h, zy + h)
            suffix = "_zoom"
        png = os.path.join(a.out, "%s_%04d%s.png" % (name, i, suffix))
        draw_scan(s, png, "%s scan %d (stamp %.3f): raw points only" % (name, i, s["stamp"]),
                  view=view, size=(1000, 1000) if a.zoom else (1750, 1000))
        print(png)


def read_features(csv_path):
    """lidarseg-features' features.csv: doors by scan index."""
    out = {}
    with open(csv_path, newline="") as f:
        for row in csv.DictReader(f):
            if not row["type"].startswith("door"):
                continue
            out.setdefault(int(row["scan"]), []).append(
                {"type": row["type"], "x": float(row["x"]), "y": float(row["y"]),
                 "theta": float(row["theta"]), "width": float(row["width"]),
                 "t": float(row["t"])})
    return out


def find_log(shared, name):
    for p in glob.glob(os.path.join(shared, "*", name + ".*")):
        if p.endswith((".log.gz", ".log", ".clf", ".clf.gz")):
            return p
    return None


def cmd_evaluate(a):
    labels = read_all_labels(a.labels)
    logs = sorted({k[0] for k in labels})
    os.makedirs(a.out, exist_ok=True)
    detections = {}
    scans_of = {}
    for name in logs:
        path = find_log(a.shared, name)
        if path is None:
            print("SKIP: log %s not found under %s" % (name, a.shared))
            return 77
        out = os.path.join(a.out, name)
        cmd = [os.path.join(a.bin, "lidarseg-features"), path, "-q", "-o", out]
        if a.config:
            cmd += ["-c", a.config]
        subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
        feats = read_features(os.path.join(out, "features.csv"))
        scans_of[name] = read_carmen(path)
        for i, dets in feats.items():   # lidarseg's scan numbering is this script's
            if any(abs(d["t"] - scans_of[name][i]["stamp"]) > 1e-3 for d in dets):
                raise ValueError("%s scan %d: lidarseg's stamp differs from the log's" % (name, i))
        for key in (k for k in labels if k[0] == name):
            scan = scans_of[name][key[1]]
            for lab in labels[key]:
                if abs(lab["stamp"] - scan["stamp"]) > 1e-3:
                    raise ValueError("%s scan %d: label stamp %.3f, log stamp %.3f"
                                     % (name, key[1], lab["stamp"], scan["stamp"]))
            detections[key] = feats.get(key[1], [])
    per_log = {name: score({k: v for k, v in labels.items() if k[0] == name}, detections,
                           a.tol, a.range) for name in logs}
    total = score(labels, detections, a.tol, a.range)
    lines = ["| log | scans labelled | with doors | doors labelled | ambiguous (excluded) | found | "
             "recall | detections ≤ %g m | true | false | precision |" % a.range,
             "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for name, s in list(per_log.items()) + [("**all**", total)]:
        lines.append("| %s | %d | %d | %d | %d | %d | %.3f | %d | %d | %d | %.3f |" % (
            name, s["scans"], s["scans_with_doors"], s["labels"], s["ambiguous"], s["found"],
            s["recall"], s["detections"], s["true_detections"], s["false_detections"],
            s["precision"]))
    lines.append("")
    lines.append("Match: detected door centre within %.2f m of the labelled centre (middle of the "
                 "two jambs), one to one, pairs of the right kind first, then nearest first. "
                 "Detections beyond %g m: %d (not scored); on ambiguous labels: %d (not scored)."
                 % (a.tol, a.range, total["beyond_range"], total["on_ambiguous"]))
    r_lo, r_hi = wilson(total["found"], total["labels"])
    p_lo, p_hi = wilson(total["true_detections"], total["detections"])
    lines.append("")
    lines.append("95 %% Wilson intervals (all): recall %.2f–%.2f, precision %.2f–%.2f."
                 % (r_lo, r_hi, p_lo, p_hi))
    counted = [(k, l) for k in sorted(labels) for l in labels[k]
               if l["kind"] != "none" and not l["ambiguous"]]
    found = {(k, id(l)) for k, l, _ in total["hits"]}
    def share(sel):
        n = len(sel)
        f = sum(1 for k, l in sel if (k, id(l)) in found)
        return "%d / %d" % (f, n)
    lines.append("")
    lines.append("Recall by labelled width: 0.6–1.3 m %s; 1.3–2.2 m %s. By kind: open %s; "
                 "closed %s. Found with the labelled kind: %d of %d." % (
                     share([c for c in counted if c[1]["width"] < 1.3]),
                     share([c for c in counted if c[1]["width"] >= 1.3]),
                     share([c for c in counted if c[1]["kind"] == "open"]),
                     share([c for c in counted if c[1]["kind"] == "closed"]),
                     sum(1 for _, l, d in total["hits"] if d["type"] == "door_" + l["kind"]),
                     len(total["hits"])))
    alt = []
    for t in a.also_tol:
        s2 = score(labels, detections, t, a.range)
        alt.append("%.2f m: recall %.3f (%d / %d), precision %.3f (%d / %d)" % (
            t, s2["recall"], s2["found"], s2["labels"], s2["precision"], s2["true_detections"],
            s2["detections"]))
    if alt:
        lines.append("")
        lines.append("Other match distances (for reading only; the labels' README fixes 0.3 m): "
                     + "; ".join(alt) + ".")
    report = "\n".join(lines)
    print(report)
    with open(os.path.join(a.out, "report.md"), "w") as f:
        f.write(report + "\n")
    with open(os.path.join(a.out, "report.json"), "w") as f:
        json.dump({n: {k: v for k, v in s.items() if k not in ("missed", "false", "hits")}
                   for n, s in list(per_log.items()) + [("all", total)]}, f, indent=1)
    with open(os.path.join(a.out, "failures.csv"), "w") as f:
        f.write("log,scan,what,x,y,width,type\n")
        for key, lab in total["missed"]:
            f.write("%s,%d,missed,%.3f,%.3f,%.3f,%s\n" % (key[0], key[1], lab["centre"][0],
                                                         lab["centre"][1], lab["width"], lab["kind"]))
        for key, det in total["false"]:
            f.write("%s,%d,false,%.3f,%.3f,%.3f,%s\n" % (key[0], key[1], det["x"], det["y"],
                                                        det["width"], det["type"]))
    if a.figures > 0:
        fig = os.path.join(a.out, "figures")
        os.makedirs(fig, exist_ok=True)
        count = {"missed": 0, "false": 0}
        for what, items in (("missed", total["missed"]), ("false", total["false"])):
            for key, item in items:
                if count[what] >= a.figures:
                    continue
                count[what] += 1
                cx, cy = item["centre"] if what == "missed" else (item["x"], item["y"])
                h = a.zoom
                png = os.path.join(fig, "%s_%s_%04d_%+.1f_%+.1f.png" % (what, key[0], key[1], cx, cy))
                draw_scan(scans_of[key[0]][key[1]], png,
                          "%s scan %d, %s door at (%.2f, %.2f): hand labels green "
                          "(ambiguous orange), detected doors red" % (key[0], key[1], what, cx, cy),
                          view=(cx - h, cx + h, cy - h, cy + h), size=(1000, 1000),
                          labels=[l for l in labels[key] if l["kind"] != "none"],
                          detections=detections[key])
        print("figures in " + fig)
    return 0


def cmd_check(a):
    labels = read_all_labels(a.labels)
    n_scans = len(labels)
    doors = sum(1 for labs in labels.values() for l in labs if l["kind"] != "none")
    amb = sum(1 for labs in labels.values() for l in labs if l["kind"] != "none" and l["ambiguous"])
    logs = sorted({k[0] for k in labels})
    print("labels parse: %d scans of %d logs (%s), %d doors of which %d ambiguous"
          % (n_scans, len(logs), ",".join(logs), doors, amb))
    if a.min_scans and n_scans < a.min_scans:
        print("FAIL: fewer than %d labelled scans" % a.min_scans)
        return 1
    if a.shared:
        for name in logs:
            path = find_log(a.shared, name)
            if path is None:
                print("log %s not under %s: stamps not checked" % (name, a.shared))
                continue
            scans = read_carmen(path)
            for key in (k for k in labels if k[0] == name):
                if key[1] >= len(scans) or abs(scans[key[1]]["stamp"] - labels[key][0]["stamp"]) > 1e-3:
                    print("FAIL: %s scan %d: stamp does not match the log" % key)
                    return 1
            print("stamps match the log: %s" % name)
    return 0


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = ap.add_subparsers(dest="cmd", required=True)
    p = sub.add_parser("select")
    p.add_argument("log")
    p.add_argument("--count", type=int, required=True)
    p.add_argument("--phase", type=float, default=0.5, help="where in each of the K strides (0..1)")
    p.add_argument("--exclude", help="a labels folder: leave out the scans it already has")
    p = sub.add_parser("render")
    p.add_argument("log")
    p.add_argument("--scans", required=True)
    p.add_argument("--out", required=True)
    p.add_argument("--zoom", help="X,Y,HALF: a square of half-side HALF (m) around (X, Y)")
    p = sub.add_parser("evaluate")
    p.add_argument("--labels", required=True)
    p.add_argument("--shared", required=True, help="the datasets folder (../shared/datasets)")
    p.add_argument("--bin", required=True, help="folder of lidarseg-features")
    p.add_argument("--config")
    p.add_argument("--out", required=True)
    p.add_argument("--tol", type=float, default=DEFAULT_TOL_M)
    p.add_argument("--range", type=float, default=DEFAULT_RANGE_M)
    p.add_argument("--also-tol", type=float, nargs="*", default=[0.2, 0.5],
                   help="other match distances to report alongside --tol")
    p.add_argument("--figures", type=int, default=0, help="pictures of up to N failures per kind")
    p.add_argument("--zoom", type=float, default=2.5, help="half-size (m) of a failure picture")
    p = sub.add_parser("check")
    p.add_argument("--labels", required=True)
    p.add_argument("--shared")
    p.add_argument("--min-scans", type=int, default=0)
    a = ap.parse_args(argv)
    return {"select": cmd_select, "render": cmd_render, "evaluate": cmd_evaluate,
            "check": cmd_check}[a.cmd](a)


if __name__ == "__main__":
    sys.exit(main())
