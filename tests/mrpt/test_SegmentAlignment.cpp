// lidarseg's segment matcher behind MRPT's map-alignment interface.
#include <algorithm>
#include <cmath>
#include <limits>
#include <iostream>

#include <gtest/gtest.h>
#include <mrpt/config/CConfigFile.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/poses/CPose3DPDFGaussian.h>
#include <mrpt/poses/CPosePDFGaussian.h>
#include <mrpt/math/wrap2pi.h>
#include <mrpt/slam/CICP.h>

#include <filesystem>
#include <fstream>
#include <vector>

#include "SyntheticScenes.h"
#include "lidarseg/mrpt/OdometryConfig.h"
#include "lidarseg/mrpt/PoseConversion.h"
#include "lidarseg/mrpt/RawlogScanReader.h"
#include "lidarseg/mrpt/ScanConverter.h"
#include "lidarseg/mrpt/SegmentAlignment.h"

namespace lidarseg::mrpt_adapter {
namespace {

using lidarseg::testing::kDeg;

// The point map of the scan seen by an LMS100-like sensor at `pose` in the office scene.
mrpt::maps::CSimplePointsMap mapAt(const Pose2D& pose, std::uint64_t seed) {
  const auto sensor = lidarseg::testing::makeSensor(541, 270.0, 0.01);
  const Scan scan = lidarseg::testing::simulate(lidarseg::testing::officeScene(), sensor, pose, seed);
  const auto obs = makeRangeScanObservation(scan, "LIDAR", mrpt::poses::CPose3D(), 0.01);
  mrpt::maps::CSimplePointsMap map;
  map.insertionOptions.minDistBetweenLaserPoints = 0.0f;
  map.loadFromRangeScan(*obs);
  return map;
}

// What loading `section` throws as std::invalid_argument; empty when it loads.
template <typename Params>
std::string loadError(Params& params, const mrpt::config::CConfigFileBase& cfg, const std::string& section) {
  try {
    params.loadFromConfigFile(cfg, section);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return {};
}

TEST(SegmentAlignment, RecoversTheMotionBetweenTwoScansWithItsCovariance) {
  const Pose2D a{1.0, 1.0, 0.0};
  const Pose2D b{1.25, 1.08, 4 * kDeg};
  const auto m1 = mapAt(a, 1), m2 = mapAt(b, 2);
  const Pose2D truth = relative(b, a);  // pose of b's frame in a's
  SegmentAlignment align;
  SegmentAlignment::TReturnInfo info;
  const auto pdf = align.AlignPDF(&m1, &m2, mrpt::poses::CPosePDFGaussian(mrpt::poses::CPose2D()), info);
  const auto& g = dynamic_cast<const mrpt::poses::CPosePDFGaussian&>(*pdf);
  EXPECT_NEAR(g.mean.x(), truth.x, 0.02);
  EXPECT_NEAR(g.mean.y(), truth.y, 0.02);
  EXPECT_NEAR(g.mean.phi(), truth.yaw, 0.3 * kDeg);
  EXPECT_EQ(info.status, MatchStatus::kOk);
  EXPECT_GE(info.matches, 3u);
  EXPECT_GT(info.segments_m1, 3u);
  EXPECT_GT(info.executionTime, 0.0);
  // A real covariance: positive definite, centimetre-level or better.
  EXPECT_GT(g.cov.det(), 0.0);
  EXPECT_LT(g.cov(0, 0), 0.01 * 0.01);
  EXPECT_LT(g.cov(2, 2), std::pow(0.5 * kDeg, 2));
}

// Maps and estimates an MRPT program may pass: an empty map, one point, points with a NaN
// coordinate (beams without return), points a million metres away, an estimate 100 km
// off. Never an exception on data, never a non-finite pose or covariance; only an estimate
// not finite or beyond +-1e7 is refused. (A NaN estimate reached the recovery search's grid
// indices: SIGSEGV.)
TEST(SegmentAlignment, OddMapsAndEstimatesGiveFiniteResultsAndANonFiniteEstimateIsRefused) {
  const auto good = mapAt({1.0, 1.0, 0.0}, 1);
  mrpt::maps::CSimplePointsMap empty, one, with_nan = good, far;
  one.insertPoint(1.0f, 2.0f, 0.0f);
  for (size_t k = 0; k < with_nan.size(); k += 3) with_nan.setPoint(k, std::nanf(""), 1.0f, 0.0f);
  for (size_t k = 0; k < good.size(); ++k) {
    float x, y, z;
    good.getPoint(k, x, y, z);
    far.insertPoint(x + 1e6f, y, z);
  }
  const std::vector<const mrpt::maps::CSimplePointsMap*> odd = {&empty, &one, &far};
  SegmentAlignment align;
  const auto finite = [](const mrpt::poses::CPosePDFGaussian& g) {
    return std::isfinite(g.mean.x()) && std::isfinite(g.mean.y()) && std::isfinite(g.mean.phi()) &&
           g.cov.array().isFinite().all();
  };
  const std::vector<const mrpt::maps::CSimplePointsMap*> all = {&empty, &one, &with_nan, &far, &good};
  for (const auto* a : all) {
    for (const auto* b : all) {
      for (const double x0 : {0.0, 1e5, -1e5}) {
        SegmentAlignment::TReturnInfo info;
        const mrpt::poses::CPose2D guess(x0, x0 == 0.0 ? 0.0 : 3.0, 0.0);
        const auto pdf = align.AlignPDF(a, b, mrpt::poses::CPosePDFGaussian(guess), info);
        const auto& g = dynamic_cast<const mrpt::poses::CPosePDFGaussian&>(*pdf);
        ASSERT_TRUE(finite(g)) << g.mean << " from " << guess;
        const bool hopeless = x0 != 0.0 || std::find(odd.begin(), odd.end(), a) != odd.end() ||
                              std::find(odd.begin(), odd.end(), b) != odd.end();
        if (hopeless) {
          EXPECT_EQ(info.track, TrackStatus::kLost) << guess;
          EXPECT_EQ(g.mean.x(), guess.x());
          EXPECT_GE(g.cov(0, 0), 0.5);
        } else {  // the same scene, some beams without return: the identity, precisely
          EXPECT_NE(info.track, TrackStatus::kLost);
          EXPECT_LT(std::hypot(g.mean.x(), g.mean.y()), 0.01) << g.mean;
          EXPECT_LT(std::abs(g.mean.phi()), 0.2 * kDeg) << g.mean;
        }
      }
    }
  }
  for (const double bad : {std::nan(""), std::numeric_limits<double>::infinity(), 1e30}) {
    try {
      align.AlignPDF(&good, &good, mrpt::poses::CPosePDFGaussian(mrpt::poses::CPose2D(0.0, bad, 0.0)));
      FAIL() << "a non-finite initial estimate was accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("SegmentAlignment::AlignPDF: the initial estimate (0, "), std::string::npos)
          << e.what();
    }
  }
}

// One object aligns many pairs (it keeps its odometry between calls): each result equals a
// fresh object's, whatever was aligned before, and a change of the options takes effect.
TEST(SegmentAlignment, RepeatedCallsEqualFreshObjectsAndFollowTheOptions) {
  const auto m1 = mapAt({1.0, 1.0, 0.0}, 1), m2 = mapAt({1.25, 1.08, 4 * kDeg}, 2);
  const auto m3 = mapAt({2.0, 1.2, -10 * kDeg}, 3), m4 = mapAt({2.3, 1.1, -4 * kDeg}, 4);
  const mrpt::poses::CPosePDFGaussian zero(mrpt::poses::CPose2D{});
  const auto meanOf = [](const mrpt::poses::CPosePDF::Ptr& pdf) {
    return dynamic_cast<const mrpt::poses::CPosePDFGaussian&>(*pdf);
  };
  SegmentAlignment reused;
  const auto first = meanOf(reused.AlignPDF(&m3, &m4, zero));  // something else before
  const auto again = meanOf(reused.AlignPDF(&m1, &m2, zero));
  SegmentAlignment fresh;
  const auto reference = meanOf(fresh.AlignPDF(&m1, &m2, zero));
  EXPECT_EQ(again.mean.x(), reference.mean.x());
  EXPECT_EQ(again.mean.y(), reference.mean.y());
  EXPECT_EQ(again.mean.phi(), reference.mean.phi());
  EXPECT_EQ(again.cov, reference.cov);
  EXPECT_EQ(meanOf(reused.AlignPDF(&m3, &m4, zero)).mean.x(), first.mean.x());
  // Options changed between calls: the next call uses them (no refinement: a coarser
  // estimate than the refined one, as a fresh object with those options gives).
  reused.options.refiner.enabled = false;
  SegmentAlignment unrefined;
  unrefined.options.refiner.enabled = false;
  const auto changed = meanOf(reused.AlignPDF(&m1, &m2, zero));
  const auto expected = meanOf(unrefined.AlignPDF(&m1, &m2, zero));
  EXPECT_EQ(changed.mean.x(), expected.mean.x());
  EXPECT_EQ(changed.mean.y(), expected.mean.y());
  EXPECT_NE(changed.mean.x(), reference.mean.x());
}

TEST(SegmentAlignment, Align3DHandlesThePlanarCaseAndRefusesTheOthers) {
  const auto m1 = mapAt({1.0, 1.0, 0.0}, 1), m2 = mapAt({1.2, 1.0, 0.0}, 2);
  SegmentAlignment align;
  const auto pdf = align.Align3DPDF(&m1, &m2, mrpt::poses::CPose3DPDFGaussian(mrpt::poses::CPose3D()));
  const auto& g = dynamic_cast<const mrpt::poses::CPose3DPDFGaussian&>(*pdf);
  EXPECT_NEAR(g.mean.x(), 0.2, 0.02);
  EXPECT_NEAR(g.mean.z(), 0.0, 1e-12);
  EXPECT_GT(g.cov(0, 0), 0.0);
  const mrpt::poses::CPose3DPDFGaussian tilted(mrpt::poses::CPose3D(0, 0, 0, 0, 0.1, 0));
  try {
    align.Align3DPDF(&m1, &m2, tilted);
    FAIL() << "a non-planar initial estimate was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("planar"), std::string::npos) << e.what();
  }
  EXPECT_THROW(align.AlignPDF(nullptr, &m2, mrpt::poses::CPosePDFGaussian()), std::invalid_argument);
}

TEST(SegmentAlignment, ParametersLoadLikeCicpsAndRejectBadKeys) {
  mrpt::config::CConfigFileMemory cfg;
  cfg.setContent(std::string("[align]\nwd_threshold_m = 0.03\nband_half_width = 4\nlevel = 2\n"));
  SegmentAlignment::TConfigParams p;
  p.loadFromConfigFile(cfg, "align");
  EXPECT_DOUBLE_EQ(p.segmentation.wall_danielsson.threshold_m, 0.03);
  EXPECT_EQ(p.matcher.band_half_width, 4u);
  EXPECT_EQ(p.level, CascadeLevel::kEroded);
  // Round trip through a file section.
  mrpt::config::CConfigFileMemory saved;
  p.saveToConfigFile(saved, "copy");
  SegmentAlignment::TConfigParams q;
  q.loadFromConfigFile(saved, "copy");
  EXPECT_EQ(q.segmentation.wall_danielsson.threshold_m, 0.03);  // exactly: the shortest text reads back
  EXPECT_EQ(q.level, CascadeLevel::kEroded);
  // Written as a person would: "0.03", not "0.029999999999999999".
  std::string text;
  saved.getContent(text);
  EXPECT_NE(text.find("wd_threshold_m = 0.03\n"), std::string::npos) << text;
  EXPECT_EQ(text.find("9999999"), std::string::npos) << text;
  // Unknown key, bad level.
  cfg.setContent(std::string("[align]\nwd_treshold_m = 0.03\n"));
  const std::string misspelt = loadError(p, cfg, "align");
  EXPECT_NE(misspelt.find("wd_treshold_m"), std::string::npos) << "misspelt key: '" << misspelt << "'";
  cfg.setContent(std::string("[align]\nlevel = 7\n"));
  EXPECT_THROW(p.loadFromConfigFile(cfg, "align"), std::invalid_argument);
}

// CICP's TConfigParams reads every key with its current value as the default, so a file
// without the algorithm's section leaves the options as they are; MRPT code relies on it.
TEST(SegmentAlignment, MissingSectionKeepsTheDefaultsLikeCicp) {
  const SegmentAlignment::TConfigParams defaults;
  mrpt::config::CConfigFileMemory ini;
  ini.setContent(std::string("[segmentation]\nwd_threshold_m = 0.03\n[matcher]\nmax_weight = 2\n"));
  SegmentAlignment::TConfigParams p;
  EXPECT_NO_THROW(p.loadFromConfigFile(ini, "segment_alignment"));
  EXPECT_EQ(p.segmentation.wall_danielsson.threshold_m,
            defaults.segmentation.wall_danielsson.threshold_m);
  EXPECT_EQ(p.matcher.max_weight, defaults.matcher.max_weight);
  EXPECT_EQ(p.matcher.iterations, defaults.matcher.iterations);
  EXPECT_EQ(p.level, defaults.level);

  // (MRPT 2.5's setContentFromYAML throws on a section of a single key: two keys each.)
  mrpt::config::CConfigFileMemory yaml;
  yaml.setContentFromYAML(std::string("matcher:\n  max_weight: 2\n  iterations: 3\n"));
  EXPECT_NO_THROW(p.loadFromConfigFile(yaml, "segment_alignment"));
  EXPECT_EQ(p.matcher.max_weight, defaults.matcher.max_weight);

  // As with CICP, values set before are kept (they are the defaults only of a fresh object).
  p.matcher.iterations = 5;
  p.loadFromConfigFile(mrpt::config::CConfigFileMemory(), "segment_alignment");
  EXPECT_EQ(p.matcher.iterations, 5u);

  // The section, when present, is read as before.
  yaml.setContentFromYAML(std::string("segment_alignment:\n  max_weight: 2\n  level: 1\n"));
  p.loadFromConfigFile(yaml, "segment_alignment");
  EXPECT_DOUBLE_EQ(p.matcher.max_weight, 2.0);
  EXPECT_EQ(p.level, CascadeLevel::kFused);
}

// A present key with a bad value is still an error, whose message names the key, and the
// options are left unchanged.
TEST(SegmentAlignment, BadValueInThePresentSectionIsRejectedNamingTheKey) {
  const struct {
    const char* text;
    const char* key;
  } cases[] = {
      {"[segment_alignment]\ncog_gate_m = -1\n", "cog_gate_m"},
      {"[segment_alignment]\nmax_weight = abc\n", "max_weight"},
      {"[segment_alignment]\nlevel = 7\n", "level"},
      {"[segment_alignment]\nwd_min_points = 2.5\n", "wd_min_points"},
  };
  for (const auto& c : cases) {
    mrpt::config::CConfigFileMemory cfg;
    cfg.setContent(std::string(c.text));
    SegmentAlignment::TConfigParams p;
    try {
      p.loadFromConfigFile(cfg, "segment_alignment");
      ADD_FAILURE() << "accepted: " << c.text;
    } catch (const std::invalid_argument& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find(c.key), std::string::npos) << what;
      EXPECT_NE(what.find("segment_alignment"), std::string::npos) << what;
    }
    EXPECT_EQ(p.level, SegmentAlignment::TConfigParams().level);
    EXPECT_EQ(p.matcher.cog_gate_m, MatcherParams().cog_gate_m);
  }
  mrpt::config::CConfigFileMemory yaml;
  yaml.setContentFromYAML(std::string("segment_alignment:\n  level: 1\n  outlier_sigmas: 0\n"));
  SegmentAlignment::TConfigParams p;
  try {
    p.loadFromConfigFile(yaml, "segment_alignment");
    FAIL() << "outlier_sigmas = 0 accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("outlier_sigmas"), std::string::npos) << e.what();
  }
}

// goodness and nIterations, like CICP's, are written on every call: a success, then a
// failure with the same info object, then a success again.
TEST(SegmentAlignment, GoodnessAndIterationsAreFilledOnEveryCall) {
  const auto m1 = mapAt({1.0, 1.0, 0.0}, 1), m2 = mapAt({1.25, 1.08, 4 * kDeg}, 2);
  SegmentAlignment align;
  const unsigned int max_rounds = static_cast<unsigned int>(align.options.matcher.iterations) + 1;
  SegmentAlignment::TReturnInfo info;
  info.goodness = -1.0;
  info.nIterations = 999;
  align.AlignPDF(&m1, &m2, mrpt::poses::CPosePDFGaussian(mrpt::poses::CPose2D()), info);
  ASSERT_EQ(info.status, MatchStatus::kOk);
  EXPECT_GE(info.nIterations, 1u);
  EXPECT_LE(info.nIterations, max_rounds);
  // Walls make most of the office scene: most of m2's points lie on matched segments.
  EXPECT_GT(info.goodness, 0.5);
  EXPECT_LE(info.goodness, 1.0);
  const double good = info.goodness;
  const unsigned int rounds = info.nIterations;

  // 50 m off: every couple is beyond the COG gate, nothing matches.
  align.AlignPDF(&m1, &m2, mrpt::poses::CPosePDFGaussian(mrpt::poses::CPose2D(50.0, 50.0, 0.0)),
                 info);
  EXPECT_EQ(info.status, MatchStatus::kTooFewMatches);
  EXPECT_EQ(info.matches, 0u);
  EXPECT_EQ(info.goodness, 0.0);
  EXPECT_EQ(info.nIterations, 0u);

  // Through Align3DPDF, the same figures as the planar call.
  align.Align3DPDF(&m1, &m2, mrpt::poses::CPose3DPDFGaussian(mrpt::poses::CPose3D()), info);
  EXPECT_EQ(info.status, MatchStatus::kOk);
  EXPECT_DOUBLE_EQ(info.goodness, good);
  EXPECT_EQ(info.nIterations, rounds);

  // A map aligned with itself: every segment matched, goodness is the segmented fraction.
  align.AlignPDF(&m1, &m1, mrpt::poses::CPosePDFGaussian(mrpt::poses::CPose2D()), info);
  EXPECT_EQ(info.matches, info.segments_m1);
  EXPECT_GT(info.goodness, good);
  EXPECT_LE(info.goodness, 1.0);
}

// On a real log, against MRPT's CICP from the same odometry guess: the scans two apart of
// the Telecom Faculty log (1-3, 3-5, ..., 61-63). With the odometry's point refinement
// the two agree on nearly every pair (28 of 31 when written); the segments alone on fewer
// (18).
TEST(SegmentAlignment, AgreesWithCicpOnPairsOfTheRealTelecomLog) {
  const std::string telecom =
      std::string(LIDARSEG_MRPT_DATASETS_DIR) + "/2006-01ENE-21-SENA_Telecom Faculty_one_loop_only.rawlog";
  if (!std::filesystem::exists(telecom)) GTEST_SKIP() << "missing " << telecom << " (Debian mrpt-common)";
  struct Frame {
    mrpt::maps::CSimplePointsMap points;
    mrpt::poses::CPose2D odometry;
  };
  std::vector<Frame> frames;
  RawlogScanReader reader(telecom);
  while (auto scan = reader.next()) {
    if (!scan->odometry) continue;
    Frame f;
    f.points.insertObservation(*scan->observation);
    f.odometry = *scan->odometry;
    frames.push_back(std::move(f));
    if (frames.size() == 64) break;
  }
  ASSERT_EQ(frames.size(), 64u);
  SegmentAlignment refined, segments_only;
  segments_only.options.refiner.enabled = false;
  segments_only.options.recovery = false;
  mrpt::slam::CICP icp;
  std::size_t pairs = 0, agree_refined = 0, agree_segments = 0;
  const auto agrees = [](const mrpt::poses::CPose2D& a, const mrpt::poses::CPose2D& b) {
    return std::hypot(a.x() - b.x(), a.y() - b.y()) <= 0.05 &&
           std::abs(mrpt::math::wrapToPi(a.phi() - b.phi())) <= 0.5 * kDeg;
  };
  for (std::size_t k = 1; k + 2 < frames.size(); k += 2) {
    const mrpt::poses::CPosePDFGaussian guess(frames[k + 2].odometry - frames[k].odometry);
    const auto& m1 = frames[k].points;
    const auto& m2 = frames[k + 2].points;
    const auto reference = icp.AlignPDF(&m1, &m2, guess)->getMeanVal();
    SegmentAlignment::TReturnInfo info;
    const auto with_points = refined.AlignPDF(&m1, &m2, guess, info)->getMeanVal();
    EXPECT_GE(info.goodness, 0.0);
    EXPECT_LE(info.goodness, 1.0);
    const auto alone = segments_only.AlignPDF(&m1, &m2, guess)->getMeanVal();
    ++pairs;
    agree_refined += agrees(with_points, reference) ? 1 : 0;
    agree_segments += agrees(alone, reference) ? 1 : 0;
  }
  std::cout << "pairs within 5 cm / 0.5 deg of CICP: " << agree_refined << " of " << pairs << " with refinement, "
            << agree_segments << " with segments only\n";
  EXPECT_GE(agree_refined, agree_segments);
  EXPECT_GE(static_cast<double>(agree_refined), 0.85 * static_cast<double>(pairs));  // measured: 28 of 31
}

// The tracking the tools run: over the first scans of the real Telecom log, with its wheel
// odometry as the prior, track() gives exactly the poses of the core SegmentOdometry it
// wraps, moved from the laser to the robot (T_odom_robot = S T_odom_sensor S^-1).
TEST(SegmentAlignment, TrackingTheTelecomLogGivesTheCoreOdometrysPoses) {
  const std::string telecom =
      std::string(LIDARSEG_MRPT_DATASETS_DIR) + "/2006-01ENE-21-SENA_Telecom Faculty_one_loop_only.rawlog";
  if (!std::filesystem::exists(telecom)) GTEST_SKIP() << "missing " << telecom << " (Debian mrpt-common)";
  SegmentAlignment align;
  SegmentOdometry core(align.trackingOptions);
  ScanConverter converter;
  RawlogScanReader reader(telecom);
  std::optional<mrpt::poses::CPose2D> last_odometry;
  std::size_t scans = 0, keyframes = 0;
  while (auto record = reader.next()) {
    const auto& obs = *record->observation;
    std::optional<mrpt::poses::CPose2D> increment;
    if (record->odometry && last_odometry) increment = *record->odometry - *last_odometry;
    last_odometry = record->odometry;
    const auto got = align.track(obs, increment);

    const Pose2D S = sensorOnRobot(obs);
    Scan scan = converter.convert(obs);
    scan.stamp_s = mrpt::Clock::toDouble(obs.timestamp);
    std::optional<Pose2D> sensor_prior;
    if (increment) sensor_prior = compose(compose(inverse(S), toPose2D(*increment)), S);
    const OdometryStep expected = core.process(scan, sensor_prior);
    const std::string where = "scan " + std::to_string(scans);
    EXPECT_EQ(got.core.status, expected.status) << where;
    EXPECT_EQ(got.core.keyframe, expected.keyframe) << where;
    EXPECT_EQ(got.core.T_odom_sensor.x, expected.T_odom_sensor.x) << where;
    EXPECT_EQ(got.core.T_odom_sensor.y, expected.T_odom_sensor.y) << where;
    EXPECT_EQ(got.core.T_odom_sensor.yaw, expected.T_odom_sensor.yaw) << where;
    const Pose2D robot = compose(compose(S, expected.T_odom_sensor), inverse(S));
    EXPECT_NEAR(got.robot_pose.mean.x(), robot.x, 1e-12) << where;
    EXPECT_NEAR(got.robot_pose.mean.y(), robot.y, 1e-12) << where;
    EXPECT_NEAR(got.robot_pose.mean.phi(), robot.yaw, 1e-12) << where;
    keyframes += expected.keyframe ? 1 : 0;
    if (++scans == 60) break;
  }
  ASSERT_EQ(scans, 60u);
  EXPECT_GT(keyframes, 2u);  // the keyframe was renewed: more than one pair was tracked
  // The core behind the tracking is the one that processed the last scan.
  EXPECT_EQ(align.trackingCore().lastSegmentation().levels[0].segments.size(),
            core.lastSegmentation().levels[0].segments.size());
}

// trackingOptions are read at the first track() after a reset: a reset starts a new
// odometry frame with the options it then holds, and the pairwise options are not used.
TEST(SegmentAlignment, ResetTrackingStartsAgainWithTheOptionsThenHeld) {
  const auto sensor = lidarseg::testing::makeSensor(361, 270.0, 0.005);
  const auto world = lidarseg::testing::officeScene();
  std::vector<Scan> scans;
  Pose2D robot{1.0, 1.0, 0.0};
  for (std::size_t k = 0; k < 8; ++k) {
    scans.push_back(lidarseg::testing::simulate(world, sensor, robot, 20 + k));
    scans.back().stamp_s = 10.0 + 0.1 * static_cast<double>(k);
    robot = compose(robot, Pose2D{0.05, 0.0, 0.5 * kDeg});
  }
  SegmentAlignment align;
  EXPECT_THROW(align.trackingCore(), std::logic_error);
  align.options.refiner.enabled = false;  // pairwise only: tracking must not see it
  // A pairwise alignment in the middle of the sequence does not disturb the tracking: the
  // poses equal those of an object that only tracked.
  const auto m1 = mapAt({1.0, 1.0, 0.0}, 1), m2 = mapAt({1.25, 1.08, 4 * kDeg}, 2);
  SegmentAlignment tracking_only;
  std::vector<SegmentAlignment::TTrackResult> first_run;
  for (std::size_t k = 0; k < scans.size(); ++k) {
    if (k == 4) align.AlignPDF(&m1, &m2, mrpt::poses::CPosePDFGaussian(mrpt::poses::CPose2D()));
    first_run.push_back(align.track(scans[k], Pose2D{}));
    const auto alone = tracking_only.track(scans[k], Pose2D{});
    EXPECT_EQ(first_run.back().robot_pose.mean.x(), alone.robot_pose.mean.x()) << "scan " << k;
    EXPECT_EQ(first_run.back().robot_pose.mean.y(), alone.robot_pose.mean.y()) << "scan " << k;
    EXPECT_EQ(first_run.back().robot_pose.mean.phi(), alone.robot_pose.mean.phi()) << "scan " << k;
  }
  EXPECT_TRUE(first_run.front().core.first);
  EXPECT_GT(first_run.back().core.refine.iterations, 0u);  // refined: trackingOptions' refiner
  EXPECT_NEAR(first_run.back().robot_pose.mean.x(), 0.05 * 7, 0.03);
  std::size_t keyframes = 0;
  for (std::size_t k = 1; k < first_run.size(); ++k) keyframes += first_run[k].core.keyframe ? 1 : 0;
  EXPECT_LT(keyframes, first_run.size() - 1);  // 0.35 m in all: not every scan a keyframe

  // Options changed while tracking wait for the reset.
  align.trackingOptions.keyframe_distance_m = 0.0;
  align.trackingOptions.keyframe_angle_rad = 0.0;
  align.resetTracking();
  EXPECT_THROW(align.trackingCore(), std::logic_error);
  for (std::size_t k = 0; k < scans.size(); ++k) {
    const auto step = align.track(scans[k], Pose2D{});
    EXPECT_EQ(step.core.first, k == 0);
    if (k > 0) {
      EXPECT_TRUE(step.core.keyframe) << "scan " << k;  // scan to scan now
    }
  }
  // A fresh start from the first scan: the first pose is the origin again.
  align.trackingOptions = SegmentAlignment::TTrackingParams{};
  align.resetTracking();
  const auto again = align.track(scans[0], Pose2D{});
  EXPECT_EQ(again.robot_pose.mean.x(), 0.0);
  EXPECT_EQ(again.robot_pose.mean.phi(), 0.0);
  EXPECT_EQ(align.track(scans[1], Pose2D{}).robot_pose.mean.x(), first_run[1].robot_pose.mean.x());

  // Invalid options are refused at the constructor and at the first track() after a reset.
  OdometryParams bad;
  bad.keyframe_distance_m = -1.0;
  EXPECT_THROW(SegmentAlignment(SegmentAlignment::TConfigParams{}, bad), std::invalid_argument);
  align.trackingOptions.keyframe_distance_m = -1.0;
  align.resetTracking();
  EXPECT_THROW(align.track(scans[0], Pose2D{}), std::invalid_argument);

  // A first scan that cannot be processed leaves no tracker behind: options set after it
  // still count, and the next scan is the first.
  align.trackingOptions = SegmentAlignment::TTrackingParams{};
  align.resetTracking();
  Scan one_beam = scans[0];
  one_beam.ranges_m.resize(1);
  one_beam.valid.resize(1);
  EXPECT_ANY_THROW(align.track(one_beam, Pose2D{}));
  EXPECT_THROW(align.trackingCore(), std::logic_error);
  EXPECT_TRUE(align.track(scans[0], Pose2D{}).core.first);
}

// The tracking's options load like the alignment's: one section (a tool's [odometry]
// section loads as it is), absent section = values kept, save-then-load round trip, a
// misspelt key named.
TEST(SegmentAlignment, TrackingOptionsLoadFromAToolsOdometrySection) {
  // A tool's configuration whose [odometry] keys all differ from the defaults: both loaders
  // read the same values (a key one of them ignored would keep its default and fail here).
  const std::string path = std::string(LIDARSEG_TEST_TMP_DIR) + "/tracking_odometry_section.ini";
  std::ofstream(path) << "[odometry]\nkeyframe_distance_m = 0.7\nkeyframe_angle_rad = 0.3\n"
                         "local_map_keyframes = 3\nlevel = fused\ndeskew = 0\ndoubtful_ratio = 0.8\n"
                         "prior_preference = 0.25\nsearch_preference = 0.3\n";
  mrpt::config::CConfigFile file(path);
  SegmentAlignment::TTrackingParams p;
  p.loadFromConfigFile(file, "odometry");
  const OdometryParams tools = loadOdometryParamsFile(path);
  const OdometryParams defaults;
  for (const OdometryParams* q : {&static_cast<const OdometryParams&>(p), &tools}) {
    EXPECT_EQ(q->keyframe_distance_m, 0.7);
    EXPECT_EQ(q->keyframe_angle_rad, 0.3);
    EXPECT_EQ(q->local_map_keyframes, 3u);
    EXPECT_EQ(q->level, CascadeLevel::kFused);
    EXPECT_FALSE(q->deskew);
    EXPECT_EQ(q->doubtful_ratio, 0.8);
    EXPECT_EQ(q->prior_preference, 0.25);
    EXPECT_EQ(q->search_preference, 0.3);
    // Keys the file does not give keep their defaults.
    EXPECT_EQ(q->prior_gate_sigmas, defaults.prior_gate_sigmas);
  }

  mrpt::config::CConfigFileMemory cfg;
  cfg.setContent(std::string("[track]\nkeyframe_distance_m = 0.5\nwd_threshold_m = 0.03\n"
                             "refine_max_iterations = 7\nsearch_resolution_m = 0.04\nlevel = fused\n"));
  SegmentAlignment::TTrackingParams q;
  q.loadFromConfigFile(cfg, "track");
  EXPECT_EQ(q.keyframe_distance_m, 0.5);
  EXPECT_EQ(q.segmentation.wall_danielsson.threshold_m, 0.03);
  EXPECT_EQ(q.refiner.max_iterations, 7u);
  EXPECT_EQ(q.search.resolution_m, 0.04);
  EXPECT_EQ(q.level, CascadeLevel::kFused);
  // Round trip: every key written, read back equal.
  mrpt::config::CConfigFileMemory saved;
  q.saveToConfigFile(saved, "copy");
  SegmentAlignment::TTrackingParams r;
  r.loadFromConfigFile(saved, "copy");
  mrpt::config::CConfigFileMemory resaved;
  r.saveToConfigFile(resaved, "copy");
  std::string a, b;
  saved.getContent(a);
  resaved.getContent(b);
  EXPECT_EQ(a, b);
  EXPECT_NE(a.find("keyframe_distance_m = 0.5\n"), std::string::npos) << a;
  EXPECT_NE(a.find("refine_max_iterations = 7\n"), std::string::npos) << a;
  // Absent section: kept.
  r.loadFromConfigFile(mrpt::config::CConfigFileMemory(), "track");
  EXPECT_EQ(r.keyframe_distance_m, 0.5);
  // A misspelt key is named, and nothing changes.
  cfg.setContent(std::string("[track]\nkeyframe_distance_m = 2\nkeyframe_distanse_m = 0.5\n"));
  const std::string misspelt = loadError(r, cfg, "track");
  EXPECT_NE(misspelt.find("keyframe_distanse_m"), std::string::npos) << "misspelt key: '" << misspelt << "'";
  EXPECT_EQ(r.keyframe_distance_m, 0.5);
}

// Tracking through the MRPT-facing class with a scan or a mounting a program may pass by
// mistake: a NaN or infinite stamp (every later pose became NaN), a sensor pose on the robot
// not finite or 1e300 m away (NaN and absurd poses, status ok), a wheel increment not
// finite or beyond +-1e7. Each is refused with std::invalid_argument, and the tracking goes
// on from the scans before as if the call had not been made. A backwards or huge stamp and
// a scan of NaN ranges are data: a finite result.
TEST(SegmentAlignment, TrackingRefusesWhatIsNoScanOrMountingAndGoesOn) {
  const auto sensor = lidarseg::testing::makeSensor(541, 270.0, 0.01);
  const double nan = std::nan(""), inf = HUGE_VAL;
  Scan a = lidarseg::testing::simulate(lidarseg::testing::officeScene(), sensor, {1.0, 1.0, 0.0}, 1);
  Scan b = lidarseg::testing::simulate(lidarseg::testing::officeScene(), sensor, {1.1, 1.0, 0.0}, 2);
  a.stamp_s = 0.0;
  b.stamp_s = 0.1;
  SegmentAlignment reference;
  reference.track(a, {});
  const auto expected = reference.track(b, {}).robot_pose.mean;
  struct Refused {
    double stamp;
    Pose2D mount;
    std::optional<Pose2D> increment;
    std::string says;
  };
  for (const Refused& c : std::vector<Refused>{{nan, {}, {}, "stamp nan is not finite"},
                                               {inf, {}, {}, "stamp inf is not finite"},
                                               {0.1, {nan, 0, 0}, {}, "sensor's pose on the robot (nan, 0, 0)"},
                                               {0.1, {1e300, 0, 0}, {}, "sensor's pose on the robot (1e+300, 0, 0)"},
                                               {0.1, {}, Pose2D{nan, 0, 0}, "odometry increment"},
                                               {0.1, {}, Pose2D{1e300, 0, 0}, "odometry increment"}}) {
    SegmentAlignment align;
    align.track(a, {});
    Scan bad = b;
    bad.stamp_s = c.stamp;
    try {
      align.track(bad, c.mount, c.increment);
      FAIL() << "accepted: " << c.says;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(c.says), std::string::npos) << e.what();
    }
    const auto next = align.track(b, {}).robot_pose;  // as if the bad call had not been made
    EXPECT_EQ(next.mean.x(), expected.x()) << c.says;
    EXPECT_EQ(next.mean.y(), expected.y()) << c.says;
    EXPECT_TRUE(next.cov.array().isFinite().all()) << c.says;
  }
  for (const double stamp : {-5.0, 1e300}) {  // a clock gone backwards, or far ahead: data
    SegmentAlignment align;
    align.track(a, {});
    Scan late = b;
    late.stamp_s = stamp;
    const auto step = align.track(late, {});
    EXPECT_TRUE(std::isfinite(step.robot_pose.mean.x()) && step.robot_pose.cov.array().isFinite().all()) << stamp;
  }
  SegmentAlignment align;
  align.track(a, {});
  Scan blind = b;
  for (double& r : blind.ranges_m) r = nan;
  const auto step = align.track(blind, {});
  EXPECT_EQ(step.core.status, TrackStatus::kLost);
  EXPECT_TRUE(step.robot_pose.cov.array().isFinite().all());
}

}  // namespace
}  // namespace lidarseg::mrpt_adapter
