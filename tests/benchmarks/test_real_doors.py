#!/usr/bin/env python3
"""Unit tests of tests/benchmarks/real_doors.py (standard library only; run by CTest).

  python3 test_real_doors.py LABELS_DIR [SHARED_DATASETS_DIR]

The labels in the repository must parse and obey their rules; the reader must number and
place beams as lidarseg's CarmenLogReader does; the matcher must follow lidarseg's rule on
tiny hand-made cases. With SHARED_DATASETS_DIR present, every label's stamp is checked
against its log; without it, that one test is skipped (the rest needs no data).
"""
import gzip
import math
import os
import sys
import tempfile
import unittest

sys.dont_write_bytecode = True   # no __pycache__ in the source tree
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import real_doors as rd  # noqa: E402

LABELS_DIR = None
SHARED_DIR = None


def door(x1, y1, x2, y2, kind="open", ambiguous=False):
    lab = {"kind": kind, "ambiguous": ambiguous, "j1": (x1, y1), "j2": (x2, y2)}
    lab["centre"] = ((x1 + x2) / 2, (y1 + y2) / 2)
    lab["width"] = math.dist(lab["j1"], lab["j2"])
    return lab


def det(x, y, kind="door_open"):
    return {"x": x, "y": y, "type": kind, "theta": 0.0, "width": 1.0, "t": 0.0}


class LabelsInTheRepository(unittest.TestCase):
    def test_parse_and_rules(self):
        labels = rd.read_all_labels(LABELS_DIR)
        logs = {k[0] for k in labels}
        self.assertEqual(logs, {"intel-corrected", "aces-corrected"})  # two buildings
        self.assertGreaterEqual(len(labels), 100)                       # >= 100 scans
        doors = [l for labs in labels.values() for l in labs if l["kind"] != "none"]
        counted = [l for l in doors if not l["ambiguous"]]
        self.assertGreaterEqual(len(counted), 20)
        for l in counted:
            self.assertTrue(0.5 <= l["width"] <= 2.4, l)
            self.assertLessEqual(math.hypot(*l["centre"]), rd.DEFAULT_RANGE_M + 0.3, l)
            self.assertGreaterEqual(min(l["j1"][0], l["j2"][0]), -0.2, l)  # in front (180 deg)
        for key, labs in labels.items():
            self.assertEqual(len({l["stamp"] for l in labs}), 1, key)

    def test_stamps_match_the_logs(self):
        if not SHARED_DIR or not os.path.isdir(SHARED_DIR):
            self.skipTest("no shared datasets folder: stamps not checked")
        labels = rd.read_all_labels(LABELS_DIR)
        for name in sorted({k[0] for k in labels}):
            path = rd.find_log(SHARED_DIR, name)
            if path is None:
                self.skipTest("log %s not in %s" % (name, SHARED_DIR))
            scans = rd.read_carmen(path)
            for key in (k for k in labels if k[0] == name):
                self.assertLess(key[1], len(scans))
                self.assertAlmostEqual(scans[key[1]]["stamp"], labels[key][0]["stamp"], places=3)


class LabelFileChecks(unittest.TestCase):
    def write(self, text):
        d = tempfile.mkdtemp()
        p = os.path.join(d, "x.csv")
        with open(p, "w") as f:
            f.write(text)
        return p

    HEADER = "# comment\nlog,scan,stamp,kind,x1,y1,x2,y2,ambiguous,note\n"

    def test_good_file(self):
        p = self.write(self.HEADER + "L,3,1.5,none,,,,,0,\nL,4,2.0,open,1,0.5,1,-0.5,0,\"a, b\"\n"
                       "L,4,2.0,closed,2,0.4,2,2.9,1,too wide but ambiguous\n")
        labels = rd.read_labels(p)
        self.assertEqual(sorted(labels), [("L", 3), ("L", 4)])
        self.assertEqual(labels[("L", 3)][0]["kind"], "none")
        d = labels[("L", 4)][0]
        self.assertAlmostEqual(d["width"], 1.0)
        self.assertEqual(d["centre"], (1.0, 0.0))
        self.assertEqual(d["note"], "a, b")
        self.assertTrue(labels[("L", 4)][1]["ambiguous"])

    def test_bad_files(self):
        bad = ["L,1,1.0,window,1,0,1,1,0,\n",          # unknown kind
               "L,1,1.0,open,1,0,,,0,\n",              # a jamb missing
               "L,1,1.0,open,1,0,1,3,0,\n",            # 3 m: not a door unless ambiguous
               "L,1,1.0,open,1,0,1,1,yes,\n",          # ambiguous not 0/1
               "L,1,1.0,none,,,,,0,\nL,1,1.0,open,1,0,1,1,0,\n"]  # none and a door
        for body in bad:
            with self.assertRaises(ValueError, msg=body):
                rd.read_labels(self.write(self.HEADER + body))


class CarmenReader(unittest.TestCase):
    def test_numbering_angles_and_invalid_beams(self):
        d = tempfile.mkdtemp()
        p = os.path.join(d, "t.log.gz")
        r181 = ["2.0"] * 181
        r181[90] = "32.766"      # SICK error code: no point
        r180 = ["1.0"] * 180
        r180[0] = "50"           # at the maximum range (50 m default): no return
        with gzip.open(p, "wt") as f:
            f.write("# test\nPARAM robot_frontlaser_offset 0.0 nohost 0\n")
            f.write("FLASER 181 %s 0 0 0 0 0 0 10.5 host 10.5\n" % " ".join(r181))
            f.write("ODOM 0 0 0 0 0 0 11 host 11\n")
            f.write("FLASER 3 1 1\n")   # malformed: skipped, not numbered
            f.write("FLASER 180 %s 0 0 0 0 0 0 12.25 host 12.25\n" % " ".join(r180))
        scans = rd.read_carmen(p)
        self.assertEqual([s["index"] for s in scans], [0, 1])
        self.assertEqual([s["stamp"] for s in scans], [10.5, 12.25])
        # 181 beams (odd): 180/(n-1) = 1 deg from -90 to +90; 180 beams (even): 180/n = 1 deg.
        self.assertAlmostEqual(math.degrees(scans[0]["res"]), 1.0)
        self.assertAlmostEqual(math.degrees(scans[1]["res"]), 1.0)
        p0 = rd.scan_points(scans[0])
        self.assertEqual(len(p0), 180)                       # the error code dropped
        self.assertAlmostEqual(p0[0][0], 0.0, places=9)      # first beam at -90 deg: (0, -2)
        self.assertAlmostEqual(p0[0][1], -2.0, places=9)
        self.assertAlmostEqual(p0[-1][1], 2.0, places=9)     # last at +90 deg
        self.assertEqual(len(rd.scan_points(scans[1])), 179)  # max range dropped


class Matching(unittest.TestCase):
    def test_nearest_first_one_to_one_within_tolerance(self):
        labels = [door(2, 0.5, 2, -0.5), door(2, 1.6, 2, 0.6)]      # centres (2, 0), (2, 1.1)
        dets = [det(2.1, 0.9), det(2.05, 0.05), det(2.0, 0.3)]
        lm, dm = rd.match_doors(labels, dets, 0.3)
        self.assertEqual(lm, [1, 0])          # (2,0) takes the nearest (2.05, 0.05)
        self.assertEqual(dm, [1, 0, -1])      # (2.0, 0.3) is left over: a false door
        lm, dm = rd.match_doors(labels, [det(2.0, 0.31)], 0.3)
        self.assertEqual(lm, [-1, -1])        # 0.31 m from (2, 0), 0.79 from (2, 1.1)
        lm, dm = rd.match_doors(labels, [det(2.0, 0.29)], 0.3)
        self.assertEqual(lm, [0, -1])

    def test_right_kind_first(self):
        labels = [door(2, 0.5, 2, -0.5, kind="closed"), door(2, 0.9, 2, 0.1, kind="open")]
        dets = [det(2.0, 0.25, "door_open"), det(2.0, 0.3, "door_closed")]
        # nearest first alone would pair (2, 0.25) with the closed door at 0.25 m; the right
        # kind first pairs the closed detection with the closed door, the open with the open.
        lm, _ = rd.match_doors(labels, dets, 0.3)
        self.assertEqual(lm, [1, 0])

    def test_score_excludes_ambiguous_and_far(self):
        labels = {("L", 1): [door(2, 0.5, 2, -0.5), door(3, 2.5, 3, 1.5, ambiguous=True)],
                  ("L", 2): [{"kind": "none", "ambiguous": False}],
                  ("L", 3): [door(1, -1, 1, -2)]}
        dets = {("L", 1): [det(2, 0.1), det(3, 2.05), det(9, 0)],   # hit, on ambiguous, beyond 8 m
                ("L", 2): [det(1, 1)],                              # false
                ("L", 3): []}                                       # missed
        s = rd.score(labels, dets, 0.3, 8.0)
        self.assertEqual((s["scans"], s["labels"], s["ambiguous"]), (3, 2, 1))
        self.assertEqual((s["found"], s["detections"], s["true_detections"]), (1, 2, 1))
        self.assertEqual((s["on_ambiguous"], s["beyond_range"], s["false_detections"]), (1, 1, 1))
        self.assertAlmostEqual(s["recall"], 0.5)
        self.assertAlmostEqual(s["precision"], 0.5)
        self.assertEqual([k for k, _ in s["missed"]], [("L", 3)])
        self.assertEqual([k for k, _ in s["false"]], [("L", 2)])

    def test_wilson(self):
        lo, hi = rd.wilson(12, 29)
        self.assertTrue(lo < 12 / 29 < hi)
        self.assertAlmostEqual(lo, 0.2550, places=3)
        self.assertAlmostEqual(hi, 0.5923, places=3)


if __name__ == "__main__":
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    LABELS_DIR = sys.argv[1]
    SHARED_DIR = sys.argv[2] if len(sys.argv) > 2 else None
    unittest.main(argv=[sys.argv[0], "-v"])
