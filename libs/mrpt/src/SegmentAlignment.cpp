#include "lidarseg/mrpt/SegmentAlignment.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <stdexcept>

#include <mrpt/maps/CPointsMap.h>
#include <mrpt/poses/CPose3DPDFGaussian.h>
#include <mrpt/poses/CPosePDFGaussian.h>

#include "ConfigKeys.h"
#include "lidarseg/core/Angles.h"
#include "lidarseg/core/NumberText.h"
#include "lidarseg/core/ScanRecord.h"
#include "lidarseg/core/SegmentOdometry.h"
#include "lidarseg/mrpt/PoseConversion.h"
#include "KeyTables.h"

namespace lidarseg::mrpt_adapter {

namespace {

// `prefix` + `key`, interned: the key tables want names that outlive the call.
const char* prefixedKey(const char* prefix, const char* key) {
  static std::mutex mutex;
  static std::set<std::string> names;  // node-based: the pointers stay valid
  const std::lock_guard<std::mutex> lock(mutex);
  return names.insert(std::string(prefix) + key).first->c_str();
}

// The [refiner] and [search] keys in a section that also holds the [matcher] and
// [odometry] keys: prefixed refine_ and search_ (their names overlap: level, max_points).
struct PrefixedStageKeys {
  template <typename Params, typename Visitor>
  void operator()(Params& p, Visitor&& visit) const {
    detail::RefinerKeys{}(p.refiner, [&](const char* key, auto& field) { visit(prefixedKey("refine_", key), field); });
    detail::SearchKeys{}(p.search, [&](const char* key, auto& field) { visit(prefixedKey("search_", key), field); });
  }
};

// The [segmentation] keys, the [matcher] keys and the level in one section, as CICP keeps
// its keys in one, then the prefixed [refiner] and [search] keys.
struct AlignmentKeys {
  template <typename Params, typename Visitor>
  void operator()(Params& p, Visitor&& visit) const {
    detail::SegmentationKeys{}(p.segmentation, visit);
    detail::MatcherKeys{}(p.matcher, visit);
    visit("level", p.level);
    visit("recovery", p.recovery);
    PrefixedStageKeys{}(p, visit);
  }
};

// The tracking's section: the alignment's stage keys, then the [odometry] keys under their
// own names (level and recovery among them), so that a tool's [odometry] section loads.
struct TrackingKeys {
  template <typename Params, typename Visitor>
  void operator()(Params& p, Visitor&& visit) const {
    detail::SegmentationKeys{}(p.segmentation, visit);
    detail::MatcherKeys{}(p.matcher, visit);
    PrefixedStageKeys{}(p, visit);
    detail::OdometryKeys{}(p, visit);
  }
};

// The points of a map as a scan seen from the map's origin: one beam per point, in map
// order, at the point's bearing.
Scan scanOf(const mrpt::maps::CMetricMap* map, const char* which) {
  const auto* points = dynamic_cast<const mrpt::maps::CPointsMap*>(map);
  if (points == nullptr) {
    throw std::invalid_argument(std::string("SegmentAlignment: ") + which +
                                " is not a point map (CSimplePointsMap built from a 2D scan)");
  }
  const auto& xs = points->getPointsBufferRef_x();
  const auto& ys = points->getPointsBufferRef_y();
  std::vector<double> angles(xs.size());
  Scan scan;
  scan.ranges_m.resize(xs.size());
  // A point with a non-finite coordinate is an invalid beam (no return), at the bearing of
  // the finite point before it (or after it, at the start): the layout needs an angle.
  std::optional<double> last_angle;
  for (std::size_t i = 0; i < xs.size(); ++i) {
    const double x = static_cast<double>(xs[i]), y = static_cast<double>(ys[i]);
    if (std::isfinite(x) && std::isfinite(y)) {
      angles[i] = std::atan2(y, x);
      scan.ranges_m[i] = std::hypot(x, y);
      if (!last_angle) std::fill(angles.begin(), angles.begin() + static_cast<long>(i), angles[i]);
      last_angle = angles[i];
    } else {
      angles[i] = last_angle.value_or(0.0);
      scan.ranges_m[i] = std::numeric_limits<double>::quiet_NaN();
    }
  }
  // Bearings may wrap past +-pi (a 360-degree scan): keep them continuous.
  for (std::size_t i = 1; i < angles.size(); ++i) {
    while (angles[i] - angles[i - 1] > kPi) angles[i] -= 2.0 * kPi;
    while (angles[i] - angles[i - 1] < -kPi) angles[i] += 2.0 * kPi;
  }
  scan.layout = std::make_shared<const BeamLayout>(std::move(angles));
  return scan;
}

OdometryParams odometryParams(const SegmentAlignment::TConfigParams& o) {
  OdometryParams p;
  p.segmentation = o.segmentation;
  p.matcher = o.matcher;
  p.level = o.level;
  p.refiner = o.refiner;
  p.search = o.search;
  p.recovery = o.recovery;
  p.deskew = false;  // two point maps carry no beam times
  return p;
}

// Every key's value, in the table's order: equal vectors mean equal options.
std::vector<double> keyValues(SegmentAlignment::TConfigParams& o) {
  std::vector<double> values;
  AlignmentKeys{}(o, [&](const char*, auto& field) { values.push_back(static_cast<double>(field)); });
  return values;
}

// `segments2`: m2's segments at the level matched; `points2`: m2's points.
void fillInfo(const OdometryStep& step, const std::vector<Segment>& segments2, std::size_t points2,
              SegmentAlignment::TReturnInfo& info) {
  const MatchResult& r = step.match;
  info.status = r.status;
  info.track = step.status;
  info.matches = r.matches.size();
  info.segments_m2 = segments2.size();
  const bool refined = step.refine.status != RefineStatus::kFailed && step.refine.iterations > 0;
  info.nIterations = static_cast<unsigned int>(refined ? step.refine.iterations : r.iterations);
  if (refined) {
    // The fraction of m2's points (those the refinement used) within reach of m1's lines.
    info.goodness = std::clamp(step.refine.inlier_ratio, 0.0, 1.0);
    return;
  }
  // Couples are one-to-one: no point of m2 is counted twice.
  std::size_t matched_points = 0;
  for (const auto& couple : r.matches) matched_points += segments2[static_cast<std::size_t>(couple.second)].num_points;
  info.goodness = points2 == 0 ? 0.0 : std::min(1.0, static_cast<double>(matched_points) / static_cast<double>(points2));
}

}  // namespace

void SegmentAlignment::TConfigParams::validate() const {
  segmentation.validate();
  matcher.validate();
  refiner.validate();
  search.validate();
  if (static_cast<std::size_t>(level) >= kNumCascadeLevels) {
    throw std::invalid_argument("level = " + std::to_string(static_cast<std::size_t>(level)) +
                                " must be a cascade level 0..3");
  }
}

void SegmentAlignment::TConfigParams::loadFromConfigFile(const mrpt::config::CConfigFileBase& source,
                                                         const std::string& section) {
  // CICP's contract, which MRPT code relies on (one file, optional sections per algorithm):
  // an absent section leaves every field as it is. lidarseg's own loaders still require
  // theirs (decision 43); a section that is present gets the same strict checks.
  if (!source.sectionExists(section)) return;
  detail::loadKeys(*this, source, section, "configuration", {}, AlignmentKeys{});
}

void SegmentAlignment::TConfigParams::saveToConfigFile(mrpt::config::CConfigFileBase& target,
                                                       const std::string& section) const {
  detail::saveKeys(*this, target, section, AlignmentKeys{});
}

void SegmentAlignment::TTrackingParams::loadFromConfigFile(const mrpt::config::CConfigFileBase& source,
                                                           const std::string& section) {
  if (!source.sectionExists(section)) return;  // CICP's contract, as TConfigParams'
  detail::loadKeys(*this, source, section, "configuration", {}, TrackingKeys{});
}

void SegmentAlignment::TTrackingParams::saveToConfigFile(mrpt::config::CConfigFileBase& target,
                                                         const std::string& section) const {
  detail::saveKeys(*this, target, section, TrackingKeys{});
}

SegmentAlignment::SegmentAlignment(const TConfigParams& params) : options(params) { options.validate(); }

SegmentAlignment::SegmentAlignment(const TConfigParams& params, const OdometryParams& tracking)
    : options(params), trackingOptions(tracking) {
  options.validate();
  trackingOptions.validate();
}

SegmentAlignment::TTrackResult SegmentAlignment::track(const Scan& scan, const Pose2D& T_robot_sensor,
                                                       const std::optional<Pose2D>& robot_odometry_increment) {
  // Made here rather than at construction so that options set after it count; validated
  // by LaserOdometry's constructor.
  if (tracker_) return tracker_->process(scan, T_robot_sensor, robot_odometry_increment);
  // The first scan: the tracker is kept only when it was processed (a scan that throws
  // leaves the tracking state unchanged, as documented). Not built aside and moved in: the
  // core holds pointers to its own members.
  tracker_.emplace(trackingOptions);
  try {
    return tracker_->process(scan, T_robot_sensor, robot_odometry_increment);
  } catch (...) {
    tracker_.reset();
    throw;
  }
}

SegmentAlignment::TTrackResult SegmentAlignment::track(
    const mrpt::obs::CObservation2DRangeScan& scan,
    const std::optional<mrpt::poses::CPose2D>& robot_odometry_increment, std::optional<double> stamp_s) {
  if (tracker_) return tracker_->process(scan, robot_odometry_increment, stamp_s);
  tracker_.emplace(trackingOptions);  // kept only when the first scan was processed
  try {
    return tracker_->process(scan, robot_odometry_increment, stamp_s);
  } catch (...) {
    tracker_.reset();
    throw;
  }
}

void SegmentAlignment::resetTracking() { tracker_.reset(); }

const SegmentOdometry& SegmentAlignment::trackingCore() const {
  if (!tracker_) throw std::logic_error("SegmentAlignment::trackingCore: no scan tracked since the last reset");
  return tracker_->core();
}

mrpt::poses::CPosePDF::Ptr SegmentAlignment::AlignPDF(
    const mrpt::maps::CMetricMap* m1, const mrpt::maps::CMetricMap* m2,
    const mrpt::poses::CPosePDFGaussian& initial,
    mrpt::optional_ref<mrpt::slam::TMetricMapAlignmentResult> outInfo) {
  const auto t0 = std::chrono::steady_clock::now();
  options.validate();
  const auto& guess = initial.mean;
  const auto usable = [](double v) { return std::isfinite(v) && std::abs(v) <= kMaxRelativeCoordinate; };
  if (!(usable(guess.x()) && usable(guess.y()) && usable(guess.phi()))) {
    throw std::invalid_argument("SegmentAlignment::AlignPDF: the initial estimate (" + numberText(guess.x()) + ", " +
                                numberText(guess.y()) + ", " + numberText(guess.phi()) +
                                ") is not finite or beyond +-1e7 (m, rad)");
  }
  const Scan s1 = scanOf(m1, "m1"), s2 = scanOf(m2, "m2");
  // The odometry's own step on a pair of scans: m1 is the keyframe, m2 the current scan,
  // the initial estimate the prior. Whatever lidarseg-odometry does to one scan (segment
  // match, point refinement, recovery search, degenerate handling) is done here.
  // One odometry kept across calls (its segmenter, refiner and search grid allocate), made
  // again only when the options changed; reset before each pair.
  std::vector<double> key = keyValues(options);
  if (!odometry_ || key != odometry_key_) {
    odometry_.emplace(odometryParams(options));
    odometry_key_ = std::move(key);
  }
  SegmentOdometry& odometry = *odometry_;
  odometry.reset();
  odometry.process(s1);
  const std::size_t segments1 = odometry.lastSegmentation().level(options.level).segments.size();
  const OdometryStep step = odometry.process(s2, toPose2D(initial.mean));
  auto out = std::make_shared<mrpt::poses::CPosePDFGaussian>(toMrpt(step.increment), toMrpt(step.increment_covariance));
  if (outInfo) {
    auto& base = outInfo.value().get();
    base.executionTime = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (auto* info = dynamic_cast<TReturnInfo*>(&base)) {
      fillInfo(step, odometry.lastSegmentation().level(step.matched_level).segments, s2.ranges_m.size(), *info);
      info->segments_m1 = segments1;
    }
  }
  return out;
}

mrpt::poses::CPose3DPDF::Ptr SegmentAlignment::Align3DPDF(
    const mrpt::maps::CMetricMap* m1, const mrpt::maps::CMetricMap* m2,
    const mrpt::poses::CPose3DPDFGaussian& initial,
    mrpt::optional_ref<mrpt::slam::TMetricMapAlignmentResult> outInfo) {
  const auto& p = initial.mean;
  if (std::abs(p.z()) > 1e-6 || std::abs(p.pitch()) > 1e-6 || std::abs(p.roll()) > 1e-6) {
    throw std::invalid_argument(
        "SegmentAlignment::Align3DPDF: segment matching is planar; the initial estimate has z = " +
        numberText(p.z()) + ", pitch = " + numberText(p.pitch()) + ", roll = " +
        numberText(p.roll()) + " (all must be 0)");
  }
  mrpt::poses::CPosePDFGaussian initial2d(mrpt::poses::CPose2D(p.x(), p.y(), p.yaw()));
  const auto pdf2d = AlignPDF(m1, m2, initial2d, outInfo);
  const auto& g = dynamic_cast<const mrpt::poses::CPosePDFGaussian&>(*pdf2d);
  mrpt::math::CMatrixDouble66 cov;
  cov.setZero();
  // MRPT's 3D order: x y z yaw pitch roll.
  const int map2d[3] = {0, 1, 3};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) cov(map2d[i], map2d[j]) = g.cov(i, j);
  cov(2, 2) = cov(4, 4) = cov(5, 5) = 1e-12;
  return std::make_shared<mrpt::poses::CPose3DPDFGaussian>(
      mrpt::poses::CPose3D(g.mean.x(), g.mean.y(), 0.0, g.mean.phi(), 0.0, 0.0), cov);
}

}  // namespace lidarseg::mrpt_adapter
