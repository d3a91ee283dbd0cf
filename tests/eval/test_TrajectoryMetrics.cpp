#include <cmath>
#include <fstream>
#include <iomanip>
#include <random>
#include <sstream>
#include <string>

#include <Eigen/Cholesky>
#include <gtest/gtest.h>

#include "lidarseg/eval/Relations.h"
#include "lidarseg/eval/StampedTrajectory.h"
#include "lidarseg/eval/TrajectoryMetrics.h"

using namespace lidarseg;
using namespace lidarseg::eval;

namespace {

// A square loop driven at 1 m per step with a 90-degree turn every 10 steps.
StampedTrajectory squareLoop() {
  StampedTrajectory t;
  Pose2D p;
  for (int k = 0; k <= 40; ++k) {
    t.push_back({100.0 + 0.1 * k, p});
    const bool turn = (k + 1) % 10 == 0;
    p = compose(p, Pose2D{1.0, 0.0, turn ? M_PI / 2 : 0.0});
  }
  return t;
}

std::string writeTemp(const std::string& name, const std::string& text) {
  const std::string path = std::string(LIDARSEG_TEST_TMP_DIR) + "/" + name;
  std::ofstream(path) << text;
  return path;
}

}  // namespace

TEST(StampedTrajectory, TumRoundTripKeepsStampsPositionsAndYaw) {
  const StampedTrajectory t = squareLoop();
  std::ostringstream os;
  writeTum(os, t, "test");
  const StampedTrajectory back = readTum(writeTemp("roundtrip.tum", os.str()));
  ASSERT_EQ(back.size(), t.size());
  for (std::size_t k = 0; k < t.size(); ++k) {
    EXPECT_NEAR(back[k].stamp_s, t[k].stamp_s, 1e-9);
    EXPECT_NEAR(back[k].pose.x, t[k].pose.x, 1e-9);
    EXPECT_NEAR(back[k].pose.y, t[k].pose.y, 1e-9);
    EXPECT_NEAR(wrapAngle(back[k].pose.yaw - t[k].pose.yaw), 0.0, 1e-9);
  }
}

TEST(StampedTrajectory, BadLinesAreNamedWithFileAndLine) {
  const std::string p1 = writeTemp("bad1.tum", "# header\n1 0 0 0 0 0 0 1\n2 0 0 0 0 0 1\n");
  try {
    readTum(p1);
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("bad1.tum:3"), std::string::npos) << e.what();
  }
  const std::string p2 = writeTemp("bad2.tum", "1 0 0 0 0 0 0 1\n2 0 nan 0 0 0 0 1\n");
  EXPECT_THROW(readTum(p2), std::runtime_error);
  const std::string p3 = writeTemp("bad3.tum", "2 0 0 0 0 0 0 1\n1 0 0 0 0 0 0 1\n");
  try {
    readTum(p3);
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("back in time"), std::string::npos) << e.what();
  }
  EXPECT_THROW(readTum(std::string(LIDARSEG_TEST_TMP_DIR) + "/missing.tum"), std::runtime_error);
}

// A pose or relation past the logs' bound (1e6 m) is refused with its file, line and field:
// 1e300 in a ground-truth x reached results.md as "ATE inf" and a 300-digit mean, 1.7e308 in
// a relation as "inf" and "-nan" (issue 16). Stamps stay free (nanosecond clocks).
TEST(StampedTrajectory, APoseOrRelationBeyondTheLogsBoundIsRefusedWithItsPlace) {
  const std::string tum = writeTemp("huge.tum", "1 0 0 0 0 0 0 1\n2 1e300 0 0 0 0 0 1\n");
  try {
    readTum(tum);
    FAIL() << "1e300 m accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("huge.tum:2: field 2 '1e300' is beyond +-1e6"), std::string::npos) << e.what();
  }
  const std::string rel = writeTemp("huge.relations", "1 2 0.1 0 0 0 0 0.01\n2 3 1.7e308 1.7e308 0 0 0 0.01\n");
  try {
    readRelations(rel);
    FAIL() << "1.7e308 m accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("huge.relations:2: field 3 '1.7e308' is beyond +-1e6"), std::string::npos)
        << e.what();
  }
  EXPECT_EQ(readTum(writeTemp("ns.tum", "1700000000000000000 1000000 -1000000 0 0 0 0 1\n")).size(), 1u);
  // An editor's byte-order mark before the first line is no part of it.
  EXPECT_EQ(readTum(writeTemp("bom.tum", "\xEF\xBB\xBF" "1 2 3 0 0 0 0 1\n")).front().pose.x, 2.0);
}

// The quaternions were not checked (issue 16): every one multiplied by 2 gave a wrong yaw
// (atan2 of a non-unit quaternion), all-zero was read as yaw 0. Decision 108.
TEST(StampedTrajectory, QuaternionsAreNormalisedOrRefusedWithTheirLine) {
  const double s = std::sin(0.5), c = std::cos(0.5);  // yaw 1 rad
  std::ostringstream unit, doubled;
  unit << std::setprecision(17);
  doubled << std::setprecision(17);
  unit << "1 0 0 0 0 0 " << s * 1.05 << ' ' << c * 1.05 << "\n";
  const StampedTrajectory near = readTum(writeTemp("q-near.tum", unit.str()));
  ASSERT_EQ(near.size(), 1u);
  EXPECT_NEAR(near[0].pose.yaw, 1.0, 1e-12);
  doubled << "1 0 0 0 0 0 " << s << ' ' << c << "\n2 0 0 0 0 0 " << 2 * s << ' ' << 2 * c << "\n";
  const std::string p = writeTemp("q-doubled.tum", doubled.str());
  try {
    readTum(p);
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()), p + ":2: not a unit quaternion (norm 2; qx qy qz qw must have a norm from 0.9 to 1.1)");
  }
  const std::string zero = writeTemp("q-zero.tum", "1 0 0 0 0 0 0 0\n");
  try {
    readTum(zero);
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()), zero + ":1: not a unit quaternion (norm 0; qx qy qz qw must have a norm from 0.9 to 1.1)");
  }
}

TEST(StampedTrajectory, NearestIndexRespectsTolerance) {
  const StampedTrajectory t = squareLoop();
  EXPECT_EQ(nearestIndex(t, 100.31, 0.02).value(), 3u);
  EXPECT_EQ(nearestIndex(t, 100.0, 0.0).value(), 0u);
  EXPECT_FALSE(nearestIndex(t, 100.35, 0.01).has_value());
  EXPECT_FALSE(nearestIndex(t, 50.0, 1.0).has_value());
  EXPECT_NEAR(pathLength(t), 40.0, 1e-9);
}

TEST(TrajectoryMetrics, PerfectEstimateHasZeroErrorsEvenInAnotherFrame) {
  const StampedTrajectory gt = squareLoop();
  StampedTrajectory est = gt;
  const Pose2D frame{3.0, -2.0, 0.7};  // an estimate expressed in its own odometry frame
  for (auto& p : est) p.pose = compose(frame, p.pose);
  const TrajectoryErrors e = evaluateTrajectory(est, gt);
  EXPECT_EQ(e.associated, gt.size());
  EXPECT_NEAR(e.path_length_m, 40.0, 1e-9);
  EXPECT_NEAR(e.final_position_error_m, 0.0, 1e-9);
  EXPECT_NEAR(e.ate_rmse_m, 0.0, 1e-9);
  EXPECT_NEAR(e.motion.dx_m.mean, 0.0, 1e-9);
  EXPECT_NEAR(e.motion.dtheta_rad.max, 0.0, 1e-9);
}

TEST(TrajectoryMetrics, ConstantMotionBiasGivesKnownTableIAndFinalError) {
  const StampedTrajectory gt = squareLoop();
  // Each step overestimated by 1 cm forward: edx = 0.01 exactly, edy = edtheta = 0.
  StampedTrajectory est;
  Pose2D p;
  est.push_back({gt[0].stamp_s, p});
  for (std::size_t k = 1; k < gt.size(); ++k) {
    Pose2D d = relative(gt[k].pose, gt[k - 1].pose);
    d.x += 0.01;
    p = compose(p, d);
    est.push_back({gt[k].stamp_s, p});
  }
  const TrajectoryErrors e = evaluateTrajectory(est, gt);
  EXPECT_NEAR(e.motion.dx_m.mean, 0.01, 1e-9);
  EXPECT_NEAR(e.motion.dx_m.stddev, 0.0, 1e-9);
  EXPECT_NEAR(e.motion.dy_m.mean, 0.0, 1e-9);
  // 40 steps of 1 cm around a closed square: the errors of opposite sides cancel.
  EXPECT_NEAR(e.final_position_error_m, 0.0, 1e-9);
  EXPECT_GT(e.ate_rmse_m, 0.01);
  EXPECT_LT(e.ate_rmse_m, 0.2);
}

TEST(TrajectoryMetrics, FinalErrorOfAHeadingBiasIsTheChordOfTheDrift) {
  StampedTrajectory gt, est;
  Pose2D g, q;
  for (int k = 0; k <= 100; ++k) {
    gt.push_back({static_cast<double>(k), g});
    est.push_back({static_cast<double>(k), q});
    g = compose(g, Pose2D{1.0, 0.0, 0.0});
    q = compose(q, Pose2D{1.0, 0.0, 0.001});
  }
  const TrajectoryErrors e = evaluateTrajectory(est, gt);
  // Expected: the end of an arc of 100 steps with 1 mrad per step.
  Pose2D expect;
  for (int k = 0; k < 100; ++k) expect = compose(expect, Pose2D{1.0, 0.0, 0.001});
  EXPECT_NEAR(e.final_position_error_m, std::hypot(expect.x - 100.0, expect.y), 1e-9);
  EXPECT_NEAR(e.final_yaw_error_rad, 0.1, 1e-9);
  EXPECT_NEAR(e.motion.dtheta_rad.mean, 0.001, 1e-12);
}

TEST(TrajectoryMetrics, TooFewAssociatedPosesIsAnError) {
  const StampedTrajectory gt = squareLoop();
  StampedTrajectory est = {{0.0, {}}, {1.0, {}}};
  EXPECT_THROW(evaluateTrajectory(est, gt), std::invalid_argument);
}

TEST(TrajectoryMetrics, AlignPositionsRecoversARigidMotion) {
  std::vector<Eigen::Vector2d> a = {{0, 0}, {1, 0}, {1, 2}, {-3, 1}};
  const Pose2D T{2.0, -1.0, 0.4};
  std::vector<Eigen::Vector2d> b;
  for (const auto& p : a) b.push_back(T * p);
  const Pose2D R = alignPositions(a, b);
  EXPECT_NEAR(R.x, T.x, 1e-12);
  EXPECT_NEAR(R.y, T.y, 1e-12);
  EXPECT_NEAR(R.yaw, T.yaw, 1e-12);
}

TEST(Relations, GeneratedRelationsOfTheTruthHaveZeroErrorAndABiasShows) {
  const StampedTrajectory gt = squareLoop();
  const auto rel = relationsFrom(gt, 2.0, 0.5);
  ASSERT_GT(rel.size(), 30u);
  const RelationErrors perfect = evaluateRelations(gt, rel);
  EXPECT_EQ(perfect.evaluated, rel.size());
  EXPECT_NEAR(perfect.translation_m.max, 0.0, 1e-9);
  StampedTrajectory scaled = gt;
  for (auto& p : scaled) {
    p.pose.x *= 1.1;
    p.pose.y *= 1.1;
  }
  const RelationErrors biased = evaluateRelations(scaled, rel);
  EXPECT_GT(biased.translation_m.mean, 0.15);  // 10 % of >= 2 m
  EXPECT_LT(biased.translation_m.mean, 0.25);
  EXPECT_NEAR(biased.rotation_rad.max, 0.0, 1e-9);
}

TEST(Relations, FileRoundTripAndUnmatchedStampsAreCounted) {
  const StampedTrajectory gt = squareLoop();
  const auto rel = relationsFrom(gt, 0.0, 0.0);
  std::ostringstream os;
  writeRelations(os, rel);
  const auto back = readRelations(writeTemp("gt.relations", os.str() + "999 1000 0 0 0 0 0 0\n"));
  ASSERT_EQ(back.size(), rel.size() + 1);
  const RelationErrors e = evaluateRelations(gt, back);
  EXPECT_EQ(e.relations, rel.size() + 1);
  EXPECT_EQ(e.evaluated, rel.size());
  EXPECT_THROW(readRelations(writeTemp("bad.relations", "1 2 3\n")), std::runtime_error);
  // A file with no relation (it evaluated "0/0") and a relation of a time with itself (its
  // error was its own displacement) are refused, naming the file and line.
  const std::string empty = writeTemp("empty.relations", "# nothing\n\n");
  try {
    readRelations(empty);
    ADD_FAILURE() << "an empty relations file was read";
  } catch (const std::runtime_error& error) {
    EXPECT_EQ(std::string(error.what()), empty + ": no relation (expected lines 't1 t2 x y z roll pitch yaw')");
  }
  const std::string self = writeTemp("self.relations", "1 2 0.1 0 0 0 0 0\n32.9068 32.9068 0.1 0 0 0 0 0.1\n");
  try {
    readRelations(self);
    ADD_FAILURE() << "a relation of a time with itself was read";
  } catch (const std::runtime_error& error) {
    EXPECT_EQ(std::string(error.what()), self + ":2: a relation between a time and itself (t1 = t2)");
  }
}

TEST(Relations, ReadsTheFreiburgBenchmarkFiles) {
  const std::string path = std::string(LIDARSEG_SHARED_DATASETS_DIR) + "/freiburg-relations/intel.relations";
  if (!std::ifstream(path)) GTEST_SKIP() << "no " << path;
  const auto rel = readRelations(path);
  EXPECT_GT(rel.size(), 1000u);
  // Real relations are not ordered in time (t2 may precede t1) but never relate a time to itself.
  for (const auto& r : rel) ASSERT_NE(r.t1_s, r.t2_s);
}

// Motions from keyframes whose errors are drawn from their own covariance give a NEES that
// follows a chi-square(3): mean 3 (its standard error over 4 000 draws is 0.04), 95 % at or
// below 7.815, median 2.37. Errors drawn from twice the covariance double the mean. A motion
// whose stamp finds no true pose is left out; a singular covariance is counted apart.
TEST(TrajectoryMetrics, NeesOfErrorsDrawnFromTheirCovarianceIsChiSquareOfThree) {
  StampedTrajectory truth;
  Pose2D p;
  for (int k = 0; k <= 4000; ++k) {
    truth.push_back({10.0 + 0.02 * k, p});
    p = compose(p, Pose2D{0.02, 0.001, 0.004});
  }
  Eigen::Matrix3d C;
  C << 4e-6, 1e-6, 2e-7,  //
      1e-6, 9e-6, -3e-7,  //
      2e-7, -3e-7, 1e-6;
  const Eigen::Matrix3d L = C.llt().matrixL();
  std::mt19937 rng(7);
  std::normal_distribution<double> n01;
  const auto motions = [&](double scale) {
    std::vector<KeyframeMotion> out;
    for (std::size_t k = 5; k < truth.size(); ++k) {
      const std::size_t key = k - 1 - k % 5;  // a keyframe every 5 poses
      const Pose2D t = relative(truth[k].pose, truth[key].pose);
      const Eigen::Vector3d e = std::sqrt(scale) * (L * Eigen::Vector3d(n01(rng), n01(rng), n01(rng)));
      out.push_back({truth[key].stamp_s, truth[k].stamp_s, Pose2D{t.x + e.x(), t.y + e.y(), t.yaw + e.z()}, C});
    }
    return out;
  };
  std::vector<KeyframeMotion> consistent = motions(1.0);
  const std::size_t drawn = consistent.size();
  KeyframeMotion unmatched = consistent.back();
  unmatched.stamp_s = 1e6;  // no true pose near it
  consistent.push_back(unmatched);
  KeyframeMotion singular = consistent.front();
  singular.covariance(2, 2) = 0.0;
  singular.covariance.row(2).setZero();
  singular.covariance.col(2).setZero();
  consistent.push_back(singular);
  const NeesSummary good = evaluateNees(consistent, truth, 1e-3);
  EXPECT_EQ(good.evaluated, drawn);
  EXPECT_EQ(good.singular, 1u);
  EXPECT_NEAR(good.mean, 3.0, 0.15);
  EXPECT_NEAR(good.median, 2.37, 0.15);
  EXPECT_NEAR(good.share_within_95, 0.95, 0.015);
  const NeesSummary over = evaluateNees(motions(2.0), truth, 1e-3);
  EXPECT_NEAR(over.mean, 6.0, 0.3);
  EXPECT_LT(over.share_within_95, 0.85);
  const NeesSummary none = evaluateNees({}, truth, 1e-3);
  EXPECT_EQ(none.evaluated, 0u);
  EXPECT_EQ(none.mean, 0.0);
}
