#include "lidarseg/inspect/Session.h"
#include "lidarseg/core/Angles.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>
#include <stdexcept>

#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/obs/CObservationImage.h>

#include "lidarseg/report/Format.h"
#include "lidarseg/mrpt/CameraRois.h"
#include "lidarseg/report/OutputFiles.h"
#include "lidarseg/report/Timing.h"
#include "lidarseg/pipeline/OdometryRun.h"
#include "lidarseg/mrpt/LidarsegConfig.h"
#include "lidarseg/mrpt/PoseConversion.h"
#include "lidarseg/core/ScanSegmenter.h"
#include "lidarseg/mrpt/FeatureConfig.h"
#include "lidarseg/mrpt/LaserLogReader.h"
#include "lidarseg/mrpt/OdometryConfig.h"
#include "lidarseg/mrpt/VisionConfig.h"

namespace lidarseg::inspect {

using mrpt_adapter::CameraRois;
using mrpt_adapter::drawRois;

using report::writeFileAtomically;

using report::Clock;
using report::microsecondsSince;
using report::fixed;

InspectorParams InspectorParams::fromFile(const std::string& path) {
  const mrpt_adapter::LidarsegConfig c = mrpt_adapter::LidarsegConfig::loadFile(path);
  InspectorParams p;
  p.odometry = c.odometry;
  p.stamps = c.stamps;
  p.features = c.features;
  p.rois = c.vision.rois;
  p.camera = c.vision.camera;
  return p;
}

namespace {
// The inspector's run: lidarseg alone, constant-velocity prior, as lidarseg-odometry's default.
std::unique_ptr<pipeline::OdometryRun> makeRun(const InspectorParams& p) {
  pipeline::RunSettings settings;
  settings.config.odometry = p.odometry;
  settings.config.stamps = p.stamps;
  return std::make_unique<pipeline::OdometryRun>(settings);
}
}  // namespace

void InspectorParams::saveIni(const std::string& path) const {
  mrpt::config::CConfigFileMemory cfg;
  mrpt_adapter::saveOdometryParams(odometry, cfg);
  mrpt_adapter::saveStampPolicyParams(stamps, cfg);
  mrpt_adapter::saveFeatureDetectorParams(features, cfg);
  mrpt_adapter::VisionConfig v;
  v.rois = rois;
  v.camera = camera;
  mrpt_adapter::saveVisionConfig(v, cfg);
  writeFileAtomically(path, "; written by lidarseg-inspect: the parameters tuned by eye\n" + cfg.getContent());
}

Session::Session(const std::string& log, const std::string& sensor_label, InspectorParams params)
    : path_(log), params_(std::move(params)) {
  params_.odometry.validate();
  params_.stamps.validate();
  params_.features.validate();
  params_.rois.validate();
  reader_ = std::make_unique<mrpt_adapter::LaserLogReader>(log, sensor_label);
  run_ = makeRun(params_);
  if (!readUpTo(0)) throw std::runtime_error(log + ": no laser scan read");
}

Session::~Session() = default;

bool Session::readUpTo(std::size_t index) {
  while (records_.size() <= index && !complete_) {
    auto record = reader_->next();
    if (!record) {
      complete_ = true;
      break;
    }
    records_.push_back(std::make_shared<mrpt_adapter::LaserRecord>(std::move(*record)));
  }
  return index < records_.size();
}

std::size_t Session::countAll() {
  readUpTo(static_cast<std::size_t>(-2));
  return records_.size();
}

std::size_t Session::indexAtTime(double stamp_s) {
  while (!complete_ && records_.back()->stamp_s < stamp_s) readUpTo(records_.size());
  const auto it = std::lower_bound(records_.begin(), records_.end(), stamp_s,
                                   [](const auto& r, double t) { return r->stamp_s < t; });
  if (it == records_.end()) return records_.size() - 1;
  const std::size_t i = static_cast<std::size_t>(it - records_.begin());
  if (i > 0 && std::abs(records_[i - 1]->stamp_s - stamp_s) < std::abs((*it)->stamp_s - stamp_s)) return i - 1;
  return i;
}

void Session::setParams(const InspectorParams& params) {
  params.odometry.validate();
  params.stamps.validate();
  params.features.validate();
  params.rois.validate();
  if (params.camera) params.camera->validate();
  params_ = params;
  run_ = makeRun(params_);
  steps_.clear();
  keyframe_segments_.reset();
  cached_.reset();
}

void Session::matchUpTo(std::size_t index) {
  while (steps_.size() <= index) {
    const auto& record = *records_[steps_.size()];
    Step s;
    const pipeline::RunStep r = run_->process(record);
    if (r.processed) {
      const auto& last = run_->lidarseg().lastStep();
      s.step = last.core;
      s.robot_pose = eval::StampedPose{r.time.output_stamp_s, mrpt_adapter::toPose2D(last.robot_pose.mean)};
      s.keyframe_index = keyframe_index_;
      s.keyframe_segments = keyframe_segments_;  // the segments this step's match used
      // A keyframe revised at this scan (decision 114): the next scans are matched with its
      // revised segments.
      if (s.step.keyframe_revision) keyframe_segments_ = s.step.keyframe_revision->segmentation;
      if (s.step.keyframe || s.step.first || !keyframe_segments_) {
        // This scan is the keyframe of the next ones; this step matched the previous one.
        keyframe_index_ = steps_.size();
        keyframe_segments_ = std::make_shared<const Segmentation>(run_->lidarseg().core().lastSegmentation());
      }
    } else {
      s.error = r.error;
      s.step.index = steps_.size();
      s.step.T_odom_sensor = steps_.empty() ? Pose2D{} : steps_.back().step.T_odom_sensor;
    }
    steps_.push_back(std::move(s));
  }
}

Pose2D Session::mountOfFirstScan() const {
  return records_.front()->sensor_on_robot;
}

std::vector<Pose2D> Session::trajectory(std::size_t index) {
  if (!readUpTo(index)) throw std::out_of_range("scan " + std::to_string(index) + " is past the end of " + path_);
  matchUpTo(index);
  std::vector<Pose2D> out;
  out.reserve(index + 1);
  for (std::size_t i = 0; i <= index; ++i) out.push_back(steps_[i].step.T_odom_sensor);
  return out;
}

eval::StampedTrajectory Session::robotTrajectory(std::size_t index) {
  if (!readUpTo(index)) throw std::out_of_range("scan " + std::to_string(index) + " is past the end of " + path_);
  matchUpTo(index);
  eval::StampedTrajectory out;
  for (std::size_t i = 0; i <= index; ++i) {
    if (steps_[i].robot_pose) out.push_back(*steps_[i].robot_pose);
  }
  return out;
}

const Frame& Session::frame(std::size_t index) {
  if (cached_ && cached_->index == index) return *cached_;
  if (!readUpTo(index)) {
    throw std::out_of_range("scan " + std::to_string(index) + " is past the end of " + path_ + " (" +
                            std::to_string(records_.size()) + " scans)");
  }
  matchUpTo(index);
  const auto& record = *records_[index];
  Frame f;
  f.index = index;
  f.stamp_s = record.stamp_s;
  f.where = record.where;
  const Step& s = steps_[index];
  f.step = s.step;
  f.keyframe_index = s.keyframe_index;
  f.keyframe_segments = s.keyframe_segments;
  f.error = s.error;
  if (f.error.empty()) {
    const ScanSegmenter segmenter(params_.odometry.segmentation);
    segmenter.process(record.scan, f.segmentation);
    const FeatureDetector detector(params_.features);
    const auto t0 = Clock::now();
    detector.detect(f.segmentation, f.features);
    f.detect_us = microsecondsSince(t0);
  }
  // The camera image that came with this scan (rawlogs: the observations read after the
  // previous scan; the simulator writes a scan's image right after it, so look one ahead).
  std::vector<const mrpt::obs::CObservation::Ptr*> candidates;
  for (const auto& o : record.companions) candidates.push_back(&o);
  if (readUpTo(index + 1)) {
    for (const auto& o : records_[index + 1]->companions) candidates.push_back(&o);
  }
  for (const auto* o : candidates) {
    const auto image = std::dynamic_pointer_cast<mrpt::obs::CObservationImage>(*o);
    if (!image || std::abs(mrpt::Clock::toDouble(image->timestamp) - f.stamp_s) > 0.05) continue;
    try {
      const CameraRois rois(path_, params_.camera, params_.rois);
      const auto boxes = rois.project(*image, mrpt_adapter::sensorPose3D(record), f.features);
      f.camera = rois.pixels(*image);
      drawRois(f.camera, boxes);
      f.rois = boxes.size();
    } catch (const std::exception& e) {
      f.error += (f.error.empty() ? "" : "; ") + std::string("camera: ") + e.what();
    }
    break;
  }
  cached_ = std::move(f);
  return *cached_;
}

namespace {

const Rgb kLevelColours[kNumCascadeLevels] = {{230, 120, 0}, {0, 170, 200}, {150, 60, 190}, {0, 150, 120}};

// A cascade level as the pictures name it: L0 to L3.
std::string levelName(std::size_t l) { return "L" + std::to_string(l); }

// A reference trajectory in the frame of the current sensor: aligned on lidarseg's first
// pose at the time of the first scan, up to the current time.
// References are robot poses; lidarseg's are the laser's: each reference pose is moved to
// the laser by its mounting pose on the robot.
std::vector<Eigen::Vector2d> referencePath(const eval::StampedTrajectory& ref, double t0, double t1,
                                           const Pose2D& T_sensor_odom, const Pose2D& mount) {
  std::vector<Eigen::Vector2d> out;
  const auto first = eval::nearestIndex(ref, t0, 1.0);
  if (!first) return out;
  const Pose2D origin_inv = inverse(compose(ref[*first].pose, mount));
  for (std::size_t i = *first; i < ref.size() && ref[i].stamp_s <= t1 + 1e-6; ++i) {
    const Pose2D p = compose(T_sensor_odom, compose(origin_inv, compose(ref[i].pose, mount)));
    out.emplace_back(p.x, p.y);
  }
  return out;
}

// A path drawn as one line from each point to the next.
LineLayer polyline(const std::vector<Eigen::Vector2d>& path, const Rgb& colour, int width_px) {
  LineLayer layer{{}, colour, width_px};
  for (std::size_t i = 1; i < path.size(); ++i) layer.lines.push_back({path[i - 1], path[i]});
  return layer;
}

// First status line: which scan (of `last`), when, segments per level, features and ROIs.
std::string scanLine(const Frame& f, const std::string& last) {
  std::ostringstream s;
  s << "scan " << f.index << " / " << last << "  t=" << fixed(f.stamp_s, 3) << " s  segments";
  for (std::size_t l = 0; l < kNumCascadeLevels; ++l) {
    s << ' ' << levelName(l) << '=' << f.segmentation.levels[l].segments.size();
  }
  s << "  features " << f.features.size();
  if (!f.camera.empty()) s << "  ROIs " << f.rois;
  return s.str();
}

// Second status line: the match against the keyframe, its uncertainty, the times.
std::string matchLine(const Frame& f) {
  const MatchResult& m = f.step.match;
  std::ostringstream s;
  if (f.step.first) {
    s << "first scan";
  } else {
    const Eigen::Matrix3d& c = f.step.increment_covariance;
    s << toString(f.step.status) << " vs " << f.keyframe_index << ": segment match " << toString(m.status) << ", "
      << m.matches.size() << " pairs";
    if (m.status == MatchStatus::kTooFewMatches) s << " (mostly " << m.rejections.dominant() << ")";
    s << "; refined " << toString(f.step.refine.status) << ", inliers " << fixed(f.step.refine.inlier_ratio * 100, 0)
      << " %; sd x " << fixed(std::sqrt(std::max(c(0, 0), 0.0)) * 100, 1) << " cm y "
      << fixed(std::sqrt(std::max(c(1, 1), 0.0)) * 100, 1) << " cm yaw "
      << fixed(std::sqrt(std::max(c(2, 2), 0.0)) * kRadToDeg, 2) << " deg";
  }
  s << "  |  W-D " << fixed(f.step.wall_danielsson_us, 0) << " us, cascade " << fixed(f.step.cascade_us, 0)
    << " us, match " << fixed(f.step.matching_us, 0) << " us, features " << fixed(f.detect_us, 1) << " us";
  return s.str();
}

// Half-width of a view holding 95 % of the points; `otherwise` without any.
double viewHalfWidth(const std::vector<Eigen::Vector2d>& points, double otherwise) {
  std::vector<double> r;
  for (const auto& p : points) {
    if (std::isfinite(p.x())) r.push_back(std::max(std::abs(p.x()), std::abs(p.y())));
  }
  if (r.empty()) return otherwise;
  std::nth_element(r.begin(), r.begin() + static_cast<long>(r.size() * 95 / 100), r.end());
  return std::clamp(r[r.size() * 95 / 100] * 1.1, 2.0, 40.0);
}

// The scan's valid points.
PointLayer rawPoints(const std::vector<Eigen::Vector2d>& points) {
  PointLayer layer{{}, report::kScanPointColour, 2};
  for (const auto& p : points) {
    if (std::isfinite(p.x())) layer.points.push_back(p);
  }
  return layer;
}

// The segments of the levels shown, each level in its colour, with their indices if asked.
void drawLevels(const Segmentation& segmentation, const Layers& layers, Drawing& d) {
  for (std::size_t l = 0; l < kNumCascadeLevels; ++l) {
    if (!layers.levels[l]) continue;
    LineLayer segs{{}, kLevelColours[l], l == 0 ? 1 : 2};
    const auto& level = segmentation.levels[l].segments;
    for (std::size_t i = 0; i < level.size(); ++i) {
      segs.lines.push_back({level[i].start, level[i].end});
      if (layers.indices) d.labels.push_back({level[i].cog, levelName(l) + ":" + std::to_string(i), kLevelColours[l]});
    }
    d.lines.push_back(std::move(segs));
    d.legend.push_back({"segments " + levelName(l), kLevelColours[l]});
  }
}

// The keyframe's segments of `level` moved into this scan's frame by the prior (the
// prediction); prior_from_keyframe is T_keyframe_current.
LineLayer predictedSegments(const Frame& f, CascadeLevel level) {
  const Pose2D to_prior = inverse(f.step.prior_from_keyframe);
  LineLayer pred{{}, {240, 170, 0}, 1};
  for (const Segment& sg : f.keyframe_segments->level(level).segments) {
    pred.lines.push_back({to_prior * sg.start, to_prior * sg.end});
  }
  return pred;
}

// The matched pairs: the keyframe segment's centre moved by the match result (T_keyframe_current)
// to the current one's. The pairs index the matched level's segments (the degenerate
// fallback's when kept).
LineLayer matchedPairs(const Frame& f) {
  const Pose2D to_match = inverse(f.step.match.T_prev_curr);
  const auto& key = f.keyframe_segments->level(f.step.matched_level).segments;
  const auto& current = f.segmentation.level(f.step.matched_level).segments;
  LineLayer pairs{{}, {220, 0, 160}, 1};
  for (const auto& [a, b] : f.step.match.matches) {
    if (a < 0 || b < 0 || static_cast<std::size_t>(a) >= key.size() || static_cast<std::size_t>(b) >= current.size()) {
      continue;
    }
    pairs.lines.push_back({to_match * key[static_cast<std::size_t>(a)].cog, current[static_cast<std::size_t>(b)].cog});
  }
  return pairs;
}

// Doors (red) and corners (green): a circle and the type's name.
void drawFeatures(const std::vector<Feature>& features, Drawing& d) {
  for (const Feature& ft : features) {
    const Rgb colour = isDoor(ft.type) ? report::kDoorColour : report::kCornerColour;
    d.circles.push_back({ft.position, isDoor(ft.type) ? 0.35 : 0.25, colour});
    d.labels.push_back({ft.position, toString(ft.type), colour});
  }
}

}  // namespace

void Session::drawTrajectories(const Frame& f, Drawing& d) {
  const Pose2D T_sensor_odom = inverse(f.step.T_odom_sensor);
  std::vector<Eigen::Vector2d> mine;
  for (const Pose2D& p : trajectory(f.index)) {
    const Pose2D q = compose(T_sensor_odom, p);
    mine.emplace_back(q.x, q.y);
  }
  d.lines.push_back(polyline(mine, report::kLidarsegColour, 2));
  d.legend.push_back({"lidarseg trajectory", report::kLidarsegColour});
  std::vector<std::string> names;
  for (const Reference& r : references_) names.push_back(r.name);
  const std::vector<Rgb> colours = report::referenceColours(names);
  for (std::size_t k = 0; k < references_.size(); ++k) {
    const std::string& name = references_[k].name;
    const Rgb colour = colours[k];
    const auto path = referencePath(references_[k].poses, records_.front()->stamp_s, f.stamp_s, T_sensor_odom,
                                    mountOfFirstScan());
    d.lines.push_back(polyline(path, colour, 1));
    d.legend.push_back({name, colour});
  }
}

Drawing Session::draw(std::size_t index, const Layers& layers) {
  const Frame& f = frame(index);
  Drawing d;
  d.status = {scanLine(f, complete_ ? std::to_string(records_.size() - 1) : "?"), matchLine(f)};
  if (!f.error.empty()) d.status.push_back("error at " + f.where + ": " + f.error);
  d.view_half_width_m = viewHalfWidth(f.segmentation.points, d.view_half_width_m);
  if (layers.trajectory) drawTrajectories(f, d);
  if (layers.raw_points) {
    d.points.push_back(rawPoints(f.segmentation.points));
    d.legend.push_back({"raw points", d.points.back().colour});
  }
  drawLevels(f.segmentation, layers, d);
  const bool matched = f.keyframe_segments && !f.step.first;
  if (matched && layers.predicted) {
    d.lines.push_back(predictedSegments(f, params_.odometry.level));
    d.legend.push_back({"keyframe segments, predicted", d.lines.back().colour});
  }
  if (matched && layers.matches) {
    d.lines.push_back(matchedPairs(f));
    d.legend.push_back({"matched pairs", d.lines.back().colour});
  }
  if (layers.features) {
    drawFeatures(f.features, d);
    d.legend.push_back({"doors", {220, 20, 20}});
    d.legend.push_back({"corners", {20, 170, 20}});
  }
  if (layers.camera) d.camera = f.camera;
  return d;
}

}  // namespace lidarseg::inspect
