#include <cmath>
#include <stdexcept>
#include <thread>

#include <gtest/gtest.h>

#include "SyntheticScenes.h"
#include "lidarseg/core/FeatureDetector.h"
#include "lidarseg/core/ScanSegmenter.h"

#include <Eigen/LU>

namespace lidarseg {
namespace {
using testing::kDeg;

// A wall y = 2 with an open door, a closed door in a 10 cm recess and a door ajar at 45
// degrees in front of the sensor (its leaf in sight); rooms behind it (back wall y = 5).
sim::World wallWithThreeDoors() {
  sim::World w;
  w.addWall({-10, 2}, {10, 2});
  w.addWall({-10, 5}, {10, 5});
  w.addDoor({sim::DoorKind::kOpen, {-4.0, 2}, {-3.1, 2}, 0.0, 0.0});
  w.addDoor({sim::DoorKind::kClosed, {2.5, 2}, {3.4, 2}, 0.1, 0.0});
  w.addDoor({sim::DoorKind::kAjar, {-0.45, 2}, {0.45, 2}, 0.0, 45 * kDeg});
  return w;
}

Eigen::Vector2d toSensor(const Pose2D& pose, const Eigen::Vector2d& world) {
  const Pose2D l = relative({world.x(), world.y(), 0.0}, pose);
  return {l.x, l.y};
}

std::vector<Feature> detectIn(const sim::World& world, const sim::SensorModel& sensor, const Pose2D& pose,
                              std::uint64_t seed = 1, const FeatureDetectorParams& params = {}) {
  const Scan scan = testing::simulate(world, sensor, pose, seed);
  SegmentationParams sp;
  sp.noise.range_sigma_m = std::max(sensor.range_sigma_m, 0.001);
  const Segmentation seg = ScanSegmenter(sp).process(scan);
  return FeatureDetector(params).detect(seg);
}

const Feature* nearest(const std::vector<Feature>& fs, const Eigen::Vector2d& p, double gate) {
  const Feature* best = nullptr;
  double best_d = gate;
  for (const Feature& f : fs) {
    const double d = (f.position - p).norm();
    if (d <= best_d) {
      best_d = d;
      best = &f;
    }
  }
  return best;
}

// Ranges below the maximum rounded to a 5 cm grid from 1 cm, as some scanners report them.
void onRangeGrid(Scan& scan, double max_range_m) {
  for (double& r : scan.ranges_m) {
    if (std::isfinite(r) && r < max_range_m) r = 0.01 + 0.05 * std::round((r - 0.01) / 0.05);
  }
}

TEST(FeatureDetector, FindsAndClassifiesOpenClosedAndAjarDoors) {
  const sim::World w = wallWithThreeDoors();
  const auto lms = testing::makeSensor(541, 270, 0.012);
  const Pose2D pose{0.0, 0.0, kPi / 2};
  for (std::uint64_t seed = 1; seed <= 5; ++seed) {
    const auto fs = detectIn(w, lms, pose, seed);
    int doors = 0;
    for (const Feature& f : fs) doors += isDoor(f.type) ? 1 : 0;
    EXPECT_EQ(doors, 3) << "seed " << seed;
    for (const sim::Door& d : w.doors()) {
      const Feature* f = nearest(fs, toSensor(pose, d.centre()), 0.1);
      ASSERT_NE(f, nullptr) << sim::toString(d.kind) << " door, seed " << seed;
      const FeatureType expected = d.kind == sim::DoorKind::kOpen     ? FeatureType::kDoorOpen
                                   : d.kind == sim::DoorKind::kClosed ? FeatureType::kDoorClosed
                                                                      : FeatureType::kDoorAjar;
      EXPECT_EQ(f->type, expected) << toString(f->type) << " seed " << seed;
      EXPECT_NEAR(f->width_m, 0.9, 0.1);
      // The wall's normal pointing away from the sensor: world +y, i.e. sensor +x.
      EXPECT_NEAR(f->theta_rad, 0.0, 2 * kDeg);
      EXPECT_GT(f->confidence, 0.5);
      EXPECT_LE(f->confidence, 1.0);
      // Jambs on the wall line, one on each side of the centre.
      EXPECT_NEAR((f->jamb_b - f->jamb_a).norm(), f->width_m, 1e-9);
      EXPECT_TRUE(f->covariance.isApprox(f->covariance.transpose()));
      EXPECT_GT(f->covariance.determinant(), 0.0);
    }
  }
}

TEST(FeatureDetector, GapsOfTheWrongWidthOrWithSomethingInThemAreNoDoors) {
  sim::World w;
  w.addWall({-10, 2}, {-3, 2});
  w.addWall({-2.6, 2}, {0, 2});   // 0.4 m gap: too narrow
  w.addWall({2.4, 2}, {4, 2});    // 2.4 m gap: too wide
  w.addWall({5, 2}, {10, 2});     // 1 m gap, but a pillar stands in it
  w.addPolygon({{4.3, 1.8}, {4.7, 1.8}, {4.7, 1.95}, {4.3, 1.95}}, sim::SurfaceKind::kClutter);
  w.addWall({-10, 5}, {10, 5});
  const auto lms = testing::makeSensor(541, 270, 0.012);
  const auto fs = detectIn(w, lms, {0.0, 0.0, kPi / 2});
  for (const Feature& f : fs) EXPECT_FALSE(isDoor(f.type)) << toString(f.type) << " at " << f.position.transpose();
}

TEST(FeatureDetector, ConcaveCornersOfARoomWithCovarianceMatchingTheirSpread) {
  const sim::World room = testing::rectangleRoom(6.0, 4.0);
  const auto sensor = testing::makeFullTurnSensor(720, 0.01);
  const Pose2D pose{2.0, 1.5, 0.3};
  const std::vector<Eigen::Vector2d> truth = {{0, 0}, {6, 0}, {6, 4}, {0, 4}};
  // Empirical spread of the detected corner (6, 4) over many noisy scans vs the predicted
  // covariance.
  std::vector<Eigen::Vector2d> samples;
  Eigen::Matrix2d predicted = Eigen::Matrix2d::Zero();
  for (std::uint64_t seed = 1; seed <= 200; ++seed) {
    const auto fs = detectIn(room, sensor, pose, seed);
    int concave = 0;
    for (const Feature& f : fs) concave += f.type == FeatureType::kCornerConcave ? 1 : 0;
    ASSERT_EQ(concave, 4) << "seed " << seed;
    for (const auto& c : truth) ASSERT_NE(nearest(fs, toSensor(pose, c), 0.05), nullptr) << c.transpose();
    const Feature* f = nearest(fs, toSensor(pose, {6, 4}), 0.05);
    samples.push_back(f->position);
    predicted += f->covariance.topLeftCorner<2, 2>() / 200.0;
    // The bisector points into the room: from the corner towards the sensor's side.
    const Eigen::Vector2d into_room = toSensor(pose, {5, 3}) - f->position;
    EXPECT_GT(std::cos(std::atan2(into_room.y(), into_room.x()) - f->theta_rad), 0.99);
  }
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const auto& s : samples) mean += s / samples.size();
  Eigen::Matrix2d empirical = Eigen::Matrix2d::Zero();
  for (const auto& s : samples) empirical += (s - mean) * (s - mean).transpose() / (samples.size() - 1);
  // Same size to within a factor of 2.5 (first-order model, endpoint-free intersection).
  const double ratio = std::sqrt(empirical.trace() / predicted.trace());
  EXPECT_GT(ratio, 0.4) << "empirical " << empirical << "\npredicted " << predicted;
  EXPECT_LT(ratio, 2.5) << "empirical " << empirical << "\npredicted " << predicted;
}

TEST(FeatureDetector, ConvexCornerOfABoxAgainstAWall) {
  // A 1 m box against the wall y = 2, seen from the front left: its front-left corner is
  // convex, where its left side meets the wall is concave.
  const sim::World w = testing::wallWithBox(2.0, 1.0);
  const auto lms = testing::makeSensor(541, 270, 0.005);
  const Pose2D pose{-1.0, -2.0, kPi / 2};
  const auto fs = detectIn(w, lms, pose);
  const Feature* convex = nearest(fs, toSensor(pose, {1.5, 1.0}), 0.1);
  ASSERT_NE(convex, nullptr);
  EXPECT_EQ(convex->type, FeatureType::kCornerConvex);
  const Feature* concave = nearest(fs, toSensor(pose, {1.5, 2.0}), 0.1);
  ASSERT_NE(concave, nullptr);
  EXPECT_EQ(concave->type, FeatureType::kCornerConcave);
}

TEST(FeatureDetector, CornersAtADoorsJambsAreNotReported) {
  // The door ajar's leaf meets the wall at the hinge: that is the door, not a corner.
  const sim::World w = wallWithThreeDoors();
  const auto lms = testing::makeSensor(541, 270, 0.0);
  const Pose2D pose{0.0, 0.0, kPi / 2};
  const auto fs = detectIn(w, lms, pose);
  for (const Feature& f : fs) {
    if (isDoor(f.type)) continue;
    EXPECT_GT((f.position - toSensor(pose, {-0.45, 2})).norm(), 0.2) << toString(f.type);
  }
}

TEST(FeatureDetector, DoorsInThickWallsDoubleAndShallowLeaves) {
  // A corridor wall 0.25 m thick (faces y = 2 and y = 2.25): an open door (its far reveal
  // is seen obliquely: no leaf), a double door ajar (hinges 0.1 m back), a closed door 1.8 m
  // wide 0.15 m deep, and a closed door whose leaf is only 3 cm behind the wall (inside the
  // wall's segment); the plain wall beside them holds no door.
  sim::World w;
  w.addWall({-10, 2}, {10, 2});
  w.addWall({-10, 2.25}, {10, 2.25});
  w.addWall({-30, 6}, {30, 6});  // the rooms behind: long enough for every beam through a door to meet it
  auto door = [](sim::DoorKind kind, double x0, double x1, double recess) {
    sim::Door d;
    d.kind = kind;
    d.jamb_a = {x0, 2};
    d.jamb_b = {x1, 2};
    d.recess_m = recess;
    d.wall_thickness_m = 0.25;
    return d;
  };
  sim::Door ajar = door(sim::DoorKind::kAjar, -3.0, -1.6, 0.1);
  ajar.double_leaf = true;
  ajar.leaf_angle_rad = 40 * kDeg;
  ajar.second_leaf_angle_rad = 30 * kDeg;
  const std::vector<std::pair<sim::Door, FeatureType>> doors = {
      {door(sim::DoorKind::kOpen, -5.0, -4.1, 0.0), FeatureType::kDoorOpen},
      {ajar, FeatureType::kDoorAjar},
      {door(sim::DoorKind::kClosed, 0.0, 1.8, 0.15), FeatureType::kDoorClosed},
      {door(sim::DoorKind::kClosed, 2.4, 3.3, 0.03), FeatureType::kDoorClosed}};
  for (const auto& [d, type] : doors) w.addDoor(d);
  const auto lms = testing::makeSensor(541, 270, 0.012);
  const Pose2D pose{0.5, 0.0, kPi / 2};
  int found = 0;
  for (std::uint64_t seed = 1; seed <= 10; ++seed) {
    const auto fs = detectIn(w, lms, pose, seed);
    int detected_doors = 0;
    for (const Feature& f : fs) detected_doors += isDoor(f.type) ? 1 : 0;
    EXPECT_LE(detected_doors, 4) << "seed " << seed;
    for (const auto& [d, type] : doors) {
      const Feature* f = nearest(fs, toSensor(pose, d.centre()), 0.15);
      if (f == nullptr || f->type != type) continue;  // a miss: counted below
      ++found;
      if (type == FeatureType::kDoorClosed) {
        EXPECT_NEAR(f->width_m, d.width(), 0.12) << d.centre().x();
      }
    }
  }
  EXPECT_GE(found, 36);  // of 40
}

// A wall 0.2 m thick (faces y = 2 and 2.2) with closed doors whose leaves stand `recess` behind
// its face.
sim::World thickWallWithClosedDoors(const std::vector<std::pair<double, double>>& spans, double recess) {
  sim::World w;
  w.addWall({-10, 2}, {10, 2});
  w.addWall({-10, 2.2}, {10, 2.2});
  for (const auto& [x0, x1] : spans) {
    sim::Door d;
    d.kind = sim::DoorKind::kClosed;
    d.jamb_a = {x0, 2};
    d.jamb_b = {x1, 2};
    d.recess_m = recess;
    d.wall_thickness_m = 0.2;
    w.addDoor(d);
  }
  return w;
}

// A leaf 1.6 cm behind the face, below the 2 cm a single range can show (sigma = 12 mm), is
// seen by ~70 beams 1.5 m away: against the ~40 points of the 0.25 m of wall on its two sides
// its offset is 6-7 standard errors. The plain wall gives no door, nor does an offset of 7 mm
// however little the noise (a finished wall's flatness tolerance).
TEST(FeatureDetector, ALeafLessThanTwoCentimetresBehindTheWallIsFoundFromItsMean) {
  const auto lms = testing::makeSensor(541, 270, 0.012);
  const Pose2D pose{0.6, 0.5, kPi / 2};
  const sim::World door = thickWallWithClosedDoors({{0.5, 1.4}}, 0.016);
  const sim::World plain = thickWallWithClosedDoors({}, 0.0);
  int found = 0, false_doors = 0;
  for (std::uint64_t seed = 1; seed <= 10; ++seed) {
    const auto fs = detectIn(door, lms, pose, seed);
    for (const Feature& f : fs) {
      if (!isDoor(f.type)) continue;
      if ((f.position - toSensor(pose, {0.95, 2.0})).norm() < 0.15 && f.type == FeatureType::kDoorClosed) {
        // The centre only: steps 1.6 cm deep are about two standard errors of the 5-point
        // windows that place the jambs, and the most significant stretch may run a few
        // decimetres into the wall on both sides (docs/features.md: width unsure).
        ++found;
      } else {
        ++false_doors;
      }
    }
    for (const Feature& f : detectIn(plain, lms, pose, seed)) false_doors += isDoor(f.type) ? 1 : 0;
  }
  // Of 10: 8 while the candidate steps were placed on 5-point windows, whose noisiest
  // stretches (one ran 0.23 m into the wall) sometimes passed where the leaf itself falls
  // just short; the steps found on bins (issue 18's speed rule) put the jambs at the leaf's
  // edges (widths 0.79-0.99 m for the true 0.9 m, against 0.79-1.43 m) and find 7.
  EXPECT_GE(found, 7);
  EXPECT_EQ(false_doors, 0);
  // 7 mm with 2 mm noise: statistically certain, but within what a plastered wall may do.
  const sim::World step = thickWallWithClosedDoors({{0.5, 1.4}}, 0.007);
  const auto quiet = testing::makeSensor(541, 270, 0.002);
  for (std::uint64_t seed = 1; seed <= 5; ++seed) {
    for (const Feature& f : detectIn(step, quiet, pose, seed)) {
      EXPECT_FALSE(isDoor(f.type)) << "seed " << seed << ": " << toString(f.type) << " at " << f.position.transpose();
    }
  }
}

// The flush-leaf pass looks for a leaf's start (end) only at the largest (smallest) step of
// each block of door_shallow_window + 1 consecutive steps (decision 82): a leaf must be found
// wherever its first and last points fall in their blocks. A leaf 1.5 cm behind the face
// (3 sigma of a 5 mm sensor: found from its mean by the flush-leaf pass, never as a segment of
// its own: with the pass off nothing is found) is moved along the wall by 5 mm at a time over
// 12 cm, more than a block (6 beams, 10.5 cm at 2 m head-on), with two seeds per place.
TEST(FeatureDetector, AShallowLeafIsFoundWhereverItsStepFallsInTheCandidateBlocks) {
  const auto quiet = testing::makeSensor(541, 270, 0.005);
  const Pose2D pose{0.6, 0.5, kPi / 2};
  FeatureDetectorParams pass_off;
  pass_off.door_shallow_min_sigmas = 0.0;
  int found = 0, found_without_pass = 0, false_doors = 0;
  for (int shift = 0; shift < 24; ++shift) {
    const double x0 = 0.5 + 0.005 * shift;
    const sim::World door = thickWallWithClosedDoors({{x0, x0 + 0.9}}, 0.015);
    const Eigen::Vector2d centre = toSensor(pose, {x0 + 0.45, 2.0});
    for (std::uint64_t seed = 1; seed <= 2; ++seed) {
      const std::uint64_t s = 100 * seed + static_cast<std::uint64_t>(shift);
      for (const Feature& f : detectIn(door, quiet, pose, s)) {
        if (!isDoor(f.type)) continue;
        if ((f.position - centre).norm() < 0.15 && f.type == FeatureType::kDoorClosed) {
          ++found;
        } else {
          ++false_doors;
        }
      }
      for (const Feature& f : detectIn(door, quiet, pose, s, pass_off)) found_without_pass += isDoor(f.type) ? 1 : 0;
    }
  }
  EXPECT_GE(found, 46);  // of 48 (48 with the code of decision 82 and before)
  EXPECT_EQ(false_doors, 0);
  EXPECT_EQ(found_without_pass, 0);
}

// Where the beams are dense the flush-leaf pass looks for the candidate steps on bins of
// several points, each at most door_min_wall_m / door_shallow_window (5 cm) long along the
// wall (issue 18's speed rule), then places each step at the point of the bins beside its
// boundary where the two windows differ most. A leaf 1.5 cm behind the face (3 sigma of a
// 5 mm sensor: found by the flush-leaf pass only, never as a segment of its own) seen
// head-on from 1 m (beams 8.7 mm apart: about six points per bin), moved by 5 mm at a time
// over 12 cm: found every time, its jambs 4 mm from the leaf's steps on average (the bins'
// boundaries alone leave them on the 5 cm grid: 13 mm off on average).
TEST(FeatureDetector, ShallowLeafStepsFoundOnBinsArePlacedAtAPoint) {
  const auto quiet = testing::makeSensor(541, 270, 0.005);
  const Pose2D pose{0.0, 1.0, kPi / 2};
  FeatureDetectorParams pass_off;
  pass_off.door_shallow_min_sigmas = 0.0;
  int found = 0, found_without_pass = 0;
  double jamb_error_sum = 0.0;
  for (int shift = 0; shift < 24; ++shift) {
    const double x0 = -0.45 + 0.005 * shift, x1 = x0 + 0.9;
    const sim::World door = thickWallWithClosedDoors({{x0, x1}}, 0.015);
    const std::uint64_t seed = 300 + static_cast<std::uint64_t>(shift);
    const std::vector<Feature> fs = detectIn(door, quiet, pose, seed);
    for (const Feature& f : detectIn(door, quiet, pose, seed, pass_off)) found_without_pass += isDoor(f.type) ? 1 : 0;
    const Feature* f = nearest(fs, toSensor(pose, {0.5 * (x0 + x1), 2.0}), 0.1);
    if (f == nullptr || f->type != FeatureType::kDoorClosed) continue;
    ++found;
    // The jambs along the wall: world x, which is -y in the sensor frame (it looks along +y).
    const double a = -f->jamb_a.y(), b = -f->jamb_b.y();
    jamb_error_sum += std::abs(std::min(a, b) - x0) + std::abs(std::max(a, b) - x1);
  }
  EXPECT_EQ(found, 24);
  EXPECT_EQ(found_without_pass, 0);
  EXPECT_LT(jamb_error_sum / std::max(1, 2 * found), 0.008);
}

// Two shallow leaves (3 cm) in one wall, 1 m of wall between them: both are doors in the same
// scan (a wall may hold several; the first found must not hide the second).
TEST(FeatureDetector, OneWallHoldsSeveralShallowDoors) {
  const auto lms = testing::makeSensor(541, 270, 0.012);
  const Pose2D pose{0.0, 0.0, kPi / 2};
  const std::vector<std::pair<double, double>> spans = {{-1.5, -0.6}, {0.4, 1.3}};
  const sim::World w = thickWallWithClosedDoors(spans, 0.03);
  int found = 0;
  for (std::uint64_t seed = 1; seed <= 10; ++seed) {
    const auto fs = detectIn(w, lms, pose, seed);
    for (const auto& [x0, x1] : spans) {
      const Feature* f = nearest(fs, toSensor(pose, {0.5 * (x0 + x1), 2.0}), 0.15);
      found += f != nullptr && f->type == FeatureType::kDoorClosed ? 1 : 0;
    }
  }
  EXPECT_GE(found, 15);  // of 20 (one door per wall, as before: 10)
}

// The flush-leaf pass keeps per-thread scratch (prefix sums, steps, candidate lists) that
// grows with the longest wall seen and is reused (decisions 82, 86, 91): a scan's doors must
// not depend on what the thread detected before. Two walls with two 3 cm leaves each, for
// three window lengths (blocks of 4, 6 and 9 steps): detected in a fresh thread and again
// after 1 081-beam office scans (longer walls, other candidate lists), every field equal to
// the bit, and shallow leaves among them.
TEST(FeatureDetector, TheFlushLeafPassAnswersTheSameWhateverTheThreadDetectedBefore) {
  const auto lms = testing::makeSensor(541, 270, 0.012);
  const auto utm = testing::makeSensor(1081, 270, 0.01, 30.0);
  const Pose2D pose{0.0, 0.0, kPi / 2};
  const std::vector<std::pair<double, double>> spans = {{-1.5, -0.6}, {0.4, 1.3}};
  const sim::World wall = thickWallWithClosedDoors(spans, 0.03);
  std::vector<Segmentation> office;
  const ScanSegmenter segmenter;
  for (int i = 0; i < 4; ++i) {
    office.push_back(segmenter.process(testing::simulate(testing::officeScene(), utm, {-8.0 + 2.0 * i, 1.0, 0.1 * i}, 50 + i)));
  }
  auto sameBits = [](const Feature& a, const Feature& b) {
    return a.type == b.type && a.position == b.position && a.theta_rad == b.theta_rad && a.width_m == b.width_m &&
           a.jamb_a == b.jamb_a && a.jamb_b == b.jamb_b && a.confidence == b.confidence &&
           a.covariance == b.covariance && a.width_variance_m2 == b.width_variance_m2 &&
           a.segment_a == b.segment_a && a.segment_b == b.segment_b;
  };
  for (const std::size_t window : {3u, 5u, 8u}) {
    int shallow_found = 0;
    FeatureDetectorParams params;
    params.door_shallow_window = window;
    const FeatureDetector detector(params);
    for (std::uint64_t seed = 1; seed <= 4; ++seed) {
      const Segmentation seg = segmenter.process(testing::simulate(wall, lms, pose, seed));
      std::vector<Feature> fresh;
      std::thread([&] { detector.detect(seg, fresh); }).join();
      std::vector<Feature> after, scratch;
      for (const Segmentation& o : office) detector.detect(o, scratch);
      detector.detect(seg, after);
      ASSERT_EQ(fresh.size(), after.size()) << "window " << window << ", seed " << seed;
      for (std::size_t i = 0; i < fresh.size(); ++i) {
        EXPECT_TRUE(sameBits(fresh[i], after[i])) << "window " << window << ", seed " << seed << ", feature " << i;
      }
      for (const auto& [x0, x1] : spans) {
        const Feature* f = nearest(after, toSensor(pose, {0.5 * (x0 + x1), 2.0}), 0.15);
        shallow_found += f != nullptr && f->type == FeatureType::kDoorClosed ? 1 : 0;
      }
    }
    // The comparison covered leaves the pass found (how many it finds is
    // OneWallHoldsSeveralShallowDoors' question, not this test's).
    EXPECT_GE(shallow_found, 1) << "window " << window;
  }
}

// The scan's own geometry: the beam step is measured between neighbouring beams and the
// range noise on its walls (residual scatter over cos^2 of the incidence).
TEST(FeatureDetector, MeasuresTheScansBeamStepAndRangeNoise) {
  const sim::World room = testing::rectangleRoom(8.0, 5.0);
  const Pose2D pose{3.0, 2.0, 0.4};
  const FeatureDetector detector;
  struct Case {
    std::size_t beams;
    double fov_deg, sigma_m;
  };
  for (const Case c : {Case{541, 270, 0.012}, Case{1081, 270, 0.03}, Case{181, 180, 0.01}}) {
    const auto sensor = testing::makeSensor(c.beams, c.fov_deg, c.sigma_m);
    for (std::uint64_t seed = 1; seed <= 3; ++seed) {
      SegmentationParams sp;
      sp.noise.range_sigma_m = c.sigma_m;
      const Segmentation seg = ScanSegmenter(sp).process(testing::simulate(room, sensor, pose, seed));
      const auto g = detector.measure(seg);
      EXPECT_NEAR(g.beam_step_rad, c.fov_deg / static_cast<double>(c.beams - 1) * kDeg, 1e-9);
      // Walls cut where the noise is large read a little low: within 30 %.
      EXPECT_NEAR(g.range_sigma_m, c.sigma_m, 0.3 * c.sigma_m) << c.beams << " beams, seed " << seed;
    }
  }
}

// ACES-like ranges: on a 5 cm grid. The grid is found from the ranges alone; a plain wall
// seen head-on (long runs of beams reading one range) gives no door, a 10 cm recess does.
TEST(FeatureDetector, RangesOnAGridAreMeasuredAndTheirStaircaseIsNoDoor) {
  sim::World w;
  w.addWall({-10, 2}, {10, 2});
  w.addWall({-10, 2.25}, {10, 2.25});
  w.addWall({-10, 6}, {10, 6});
  sim::Door closed;
  closed.kind = sim::DoorKind::kClosed;
  closed.jamb_a = {1.0, 2};
  closed.jamb_b = {1.9, 2};
  closed.recess_m = 0.1;
  closed.wall_thickness_m = 0.25;
  w.addDoor(closed);
  const auto sick = testing::makeSensor(181, 180, 0.005);
  const FeatureDetector detector;
  int found = 0, false_doors = 0;
  for (std::uint64_t seed = 1; seed <= 10; ++seed) {
    const Pose2D pose{-1.0 + 0.1 * static_cast<double>(seed), 0.0, kPi / 2};
    Scan scan = testing::simulate(w, sick, pose, seed);
    const Scan raw = scan;
    onRangeGrid(scan, sick.max_range_m);
    SegmentationParams sp;
    sp.noise.range_sigma_m = 0.01;
    const Segmentation seg = ScanSegmenter(sp).process(scan);
    EXPECT_DOUBLE_EQ(detector.rangeQuantum(seg, 0, seg.points.size()), 0.05);
    EXPECT_EQ(detector.rangeQuantum(ScanSegmenter(sp).process(raw), 0, seg.points.size()), 0.0);
    for (const Feature& f : detector.detect(seg)) {
      if (!isDoor(f.type)) continue;
      if ((f.position - toSensor(pose, closed.centre())).norm() < 0.2 && f.type == FeatureType::kDoorClosed) {
        ++found;
      } else {
        ++false_doors;
      }
    }
  }
  EXPECT_EQ(false_doors, 0);
  EXPECT_GE(found, 8);  // of 10
}

// A closed leaf recessed into a thick wall, ranges on a 5 cm grid: a recess shallower than
// the grid's staircase (3.5 cm) is no door, though found from the raw ranges; one deeper than
// any grid the detector tries (10 cm: 12 and 20 cm) is found without the grid being measured
// (decision 86), as it is from the raw ranges.
TEST(FeatureDetector, ALeafIsJudgedAgainstTheRangesGridOnlyWhereTheGridDecides) {
  const auto sick = testing::makeSensor(181, 180, 0.005);
  const FeatureDetector detector;
  SegmentationParams sp;
  sp.noise.range_sigma_m = 0.01;
  for (const double recess : {0.035, 0.12, 0.2}) {
    sim::World w;
    w.addWall({-10, 2}, {10, 2});
    w.addWall({-10, 2.3}, {10, 2.3});
    sim::Door leaf;
    leaf.kind = sim::DoorKind::kClosed;
    leaf.jamb_a = {-0.45, 2};
    leaf.jamb_b = {0.45, 2};
    leaf.recess_m = recess;
    leaf.wall_thickness_m = 0.3;
    w.addDoor(leaf);
    int found_raw = 0, found_grid = 0, other = 0;
    for (std::uint64_t seed = 1; seed <= 10; ++seed) {
      const Pose2D pose{-0.5 + 0.1 * static_cast<double>(seed), 0.0, kPi / 2};
      Scan scan = testing::simulate(w, sick, pose, seed);
      const Scan raw = scan;
      onRangeGrid(scan, sick.max_range_m);
      for (const bool grid : {false, true}) {
        const Segmentation seg = ScanSegmenter(sp).process(grid ? scan : raw);
        for (const Feature& f : detector.detect(seg)) {
          if (!isDoor(f.type)) continue;
          if (f.type == FeatureType::kDoorClosed && (f.position - toSensor(pose, leaf.centre())).norm() < 0.3) {
            ++(grid ? found_grid : found_raw);
          } else {
            ++other;
          }
        }
      }
    }
    EXPECT_EQ(other, 0) << recess;
    EXPECT_GE(found_raw, 5) << recess;  // of 10
    if (recess < 0.05) {
      EXPECT_EQ(found_grid, 0) << recess;
    } else {
      EXPECT_GE(found_grid, 9) << recess;
    }
  }
}

// A wall seen at a grazing angle by a 1-degree scanner, with a few returns lost in a row (a
// dark or glossy stretch): the points are 0.3-0.4 m apart there and the lost beams leave a
// door-wide gap with nothing seen through it. No door. The same place with a real open door
// and a room behind it, seen by a scanner with 0.5-degree beams, is found.
TEST(FeatureDetector, LostReturnsOnAGrazingWallAreNoDoorARealDoorThereIsFound) {
  sim::World plain;
  plain.addWall({-10, 2}, {10, 2});
  const Pose2D pose{0.0, 0.0, kPi / 2};
  const auto sick = testing::makeSensor(181, 180, 0.01);
  const FeatureDetector detector;
  SegmentationParams sp;
  sp.noise.range_sigma_m = 0.01;
  for (std::uint64_t seed = 1; seed <= 5; ++seed) {
    Scan scan = testing::simulate(plain, sick, pose, seed);
    int lost = 0;
    for (std::size_t i = 0; i < scan.size(); ++i) {
      // Beams meeting the wall between x = 5 and 6.5 (world), 68-73 degrees off its normal.
      const double bearing = sick.layout->angle(i);
      const double x_world = -2.0 * std::tan(bearing);
      if (x_world > 5.0 && x_world < 6.5) {
        scan.ranges_m[i] = sick.max_range_m;
        ++lost;
      }
    }
    ASSERT_GE(lost, 4);
    const Segmentation seg = ScanSegmenter(sp).process(scan);
    for (const Feature& f : detector.detect(seg)) {
      EXPECT_FALSE(isDoor(f.type)) << "seed " << seed << ": " << toString(f.type) << " at " << f.position.transpose();
    }
  }
  sim::World with_door = plain;
  with_door.addWall({-30, 5}, {30, 5});  // long: the beams through the door meet it
  with_door.addDoor({sim::DoorKind::kOpen, {5.0, 2}, {6.2, 2}, 0.0, 0.0});
  const auto lms = testing::makeSensor(361, 180, 0.012);
  int found = 0;
  for (std::uint64_t seed = 1; seed <= 5; ++seed) {
    const auto fs = detectIn(with_door, lms, pose, seed);
    const Feature* f = nearest(fs, toSensor(pose, {5.6, 2.0}), 0.2);
    found += f != nullptr && f->type == FeatureType::kDoorOpen ? 1 : 0;
  }
  EXPECT_GE(found, 4);  // of 5
}

TEST(FeatureDetector, EmptyAndDegenerateInputsGiveNothing) {
  const FeatureDetector detector;
  Segmentation empty;
  EXPECT_TRUE(detector.detect(empty).empty());
  // A single straight wall: no door, no corner.
  sim::World w;
  w.addWall({-10, 2}, {10, 2});
  EXPECT_TRUE(detectIn(w, testing::makeSensor(541, 270, 0.012), {0, 0, kPi / 2}).empty());
}

TEST(FeatureDetector, ValidationNamesTheKey) {
  FeatureDetectorParams p;
  p.door_max_width_m = 0.5;  // below the minimum width
  try {
    FeatureDetector d(p);
    FAIL() << "accepted door_max_width_m < door_min_width_m";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("door_max_width_m"), std::string::npos) << e.what();
  }
  p = {};
  p.corner_min_angle_deg = 0.0;
  EXPECT_THROW(FeatureDetector{p}, std::invalid_argument);
  p = {};
  p.door_min_recess_m = 0.5;
  EXPECT_THROW(FeatureDetector{p}, std::invalid_argument);
  p = {};
  p.door_quantum_min_share = 0.1;  // chance alone puts a fifth of cm ranges on a 5 cm grid
  EXPECT_THROW(FeatureDetector{p}, std::invalid_argument);
  p = {};
  p.door_min_range_sigma_m = 0.0;
  EXPECT_THROW(FeatureDetector{p}, std::invalid_argument);
  p = {};
  p.door_gap_min_spacings = -1.0;
  EXPECT_THROW(FeatureDetector{p}, std::invalid_argument);
  p = {};
  p.door_shallow_min_recess_m = p.door_shallow_max_recess_m;
  try {
    FeatureDetector d(p);
    FAIL() << "accepted door_shallow_min_recess_m = door_shallow_max_recess_m";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("door_shallow_min_recess_m"), std::string::npos) << e.what();
  }
}

TEST(FeatureType, NamesRoundTrip) {
  for (std::size_t i = 0; i < kNumFeatureTypes; ++i) {
    const auto t = static_cast<FeatureType>(i);
    EXPECT_EQ(featureTypeFromString(toString(t)), t);
  }
  EXPECT_FALSE(featureTypeFromString("door").has_value());
}

}  // namespace
}  // namespace lidarseg
