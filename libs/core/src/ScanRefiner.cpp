#include "lidarseg/core/ScanRefiner.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include <Eigen/Eigenvalues>

#include "Validation.h"

namespace lidarseg {

namespace {

using FiniteLine = RefinementKeyframe::Line;
using KeyframeIndex = RefinementKeyframe;

// A monotonic stand-in for the bearing atan2(y, x), in [0, 4) over [0, 2 pi): the index only
// needs the order, and this costs one division.
inline double pseudoBearing(double x, double y) {
  const double ax = std::abs(x), ay = std::abs(y);
  const double sum = ax + ay;
  if (!(sum > 0.0)) return 0.0;
  if (y >= 0.0) return x >= 0.0 ? y / sum : 1.0 - x / sum;
  return x < 0.0 ? 2.0 - y / sum : 3.0 + x / sum;
}

constexpr int kBins = 2048;
static_assert((kBins & (kBins - 1)) == 0, "the bins' bounds are exact multiples");

// The normal equations of one pairing pass (yaw scaled by D), and its counts.
struct Accumulator {
  Eigen::Matrix3d H = Eigen::Matrix3d::Zero();   // robustly weighted
  Eigen::Matrix3d Hu = Eigen::Matrix3d::Zero();  // unweighted: how many points constrain what
  Eigen::Vector3d g = Eigen::Vector3d::Zero();
  double wr2 = 0.0, wsum = 0.0, inlier_r2 = 0.0;
  std::size_t paired = 0, covered = 0, inliers = 0;
  // With a sweep model: the rate's column (against x, y, scaled yaw), its own term, gradient.
  double h3[3] = {0.0, 0.0, 0.0};
  double h33 = 0.0, g3 = 0.0;
  double hu3[3] = {0.0, 0.0, 0.0};  // the same, unweighted
  double hu33 = 0.0;
};

// The constrained directions as columns (at most 3, no heap allocation per scan).
using Basis = Eigen::Matrix<double, 3, Eigen::Dynamic, 0, 3, 3>;
using Reduced = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 3, 3>;

// inliers / covered points (0 when nothing pairs).
double inlierRatioOf(const Accumulator& acc) {
  return acc.inliers == 0 ? 0.0 : static_cast<double>(acc.inliers) / static_cast<double>(std::max(acc.covered, acc.inliers));
}

bool finitePoint(const Eigen::Vector2d& p) { return std::isfinite(p.x()) && std::isfinite(p.y()); }

// The keyframe points no usable segment holds (clutter, jambs, pillars, the ends of walls
// the segmenter cut off) become features too. A point joins its next (else previous)
// neighbour when that one lies within `link_m`: a two-point finite line (point to line, as in
// PL-ICP). Without such a neighbour, a point between two valid ones that lies on their line
// (within `on_line_m`) samples a surface seen at grazing incidence: the line through the
// three. Only a point off its neighbours' line is kept alone (length 0: point to point with
// two residuals, a chair leg or a post); one with an invalid neighbour has no known shape and
// is left out.
template <typename Transform, typename Rotate>
void linkUnsegmented(const std::vector<Eigen::Vector2d>& points, const Transform& T, const Rotate& rotate,
                     double link_m, double on_line_m, KeyframeIndex& ix) {
  const std::size_t beams = points.size();
  const auto valid = [&](std::size_t k) { return k < beams && finitePoint(points[k]); };
  const auto lineThrough = [&](const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    FiniteLine l;
    const Eigen::Vector2d d = b - a;
    l.start = T(a);
    l.length = d.norm();
    l.direction = rotate(d / l.length);
    l.normal = Eigen::Vector2d(-l.direction.y(), l.direction.x());
    l.rho = l.normal.dot(l.start);
    return l;
  };
  for (std::size_t b = 0; b < beams; ++b) {
    if (ix.beam_line[b] >= 0 || !valid(b)) continue;
    const Eigen::Vector2d& p = points[b];
    const auto near = [&](std::size_t k) {
      const double d = valid(k) ? (points[k] - p).norm() : 0.0;
      return d > 0.0 && d <= link_m;
    };
    FiniteLine l;
    if (near(b + 1)) {
      l = lineThrough(p, points[b + 1]);
    } else if (b > 0 && near(b - 1)) {
      l = lineThrough(points[b - 1], p);
    } else if (b > 0 && valid(b - 1) && valid(b + 1)) {
      const Eigen::Vector2d& a = points[b - 1];
      const Eigen::Vector2d& c = points[b + 1];
      const Eigen::Vector2d ac = c - a;
      const double len = ac.norm();
      if (!(len > 0.0)) continue;
      const double off = std::abs(ac.x() * (p.y() - a.y()) - ac.y() * (p.x() - a.x())) / len;
      if (off <= on_line_m) {
        l = lineThrough(a, c);
      } else {
        l.start = T(p);  // a lone point: length 0, paired by its x and y offsets
        l.normal = l.direction = Eigen::Vector2d::Zero();
      }
    } else {
      continue;
    }
    ix.beam_line[b] = static_cast<int>(ix.lines.size());
    ix.lines.push_back(l);
  }
}

}  // namespace

void ScanRefiner::prepare(const Segmentation& keyframe, RefinementKeyframe& ix) const {
  prepare(std::vector<RefinementMapScan>{{&keyframe, Pose2D{}}}, ix);
}

void ScanRefiner::prepare(const std::vector<RefinementMapScan>& scans, RefinementKeyframe& ix) const {
  const RefinerParams& P = params_;
  ix.lines.clear();
  ix.scratch.clear();
  ix.scans = 0;
  for (const RefinementMapScan& m : scans) {
    if (m.segmentation == nullptr) continue;
    ++ix.scans;
    const Segmentation& scan = *m.segmentation;
    const Pose2D& T = m.T_key_scan;
    const double c = std::cos(T.yaw), sn = std::sin(T.yaw);
    const auto rotate = [&](const Eigen::Vector2d& v) { return Eigen::Vector2d(c * v.x() - sn * v.y(), sn * v.x() + c * v.y()); };
    // T * p without a cosine and a sine per point (the same expression as Pose2D's).
    const auto transform = [&](const Eigen::Vector2d& p) {
      return Eigen::Vector2d(T.x + c * p.x() - sn * p.y(), T.y + sn * p.x() + c * p.y());
    };
    const std::size_t beams = scan.points.size();
    ix.beam_line.assign(beams, -1);
    for (const Segment& s : scan.level(P.level).segments) {
      if (s.num_points < P.min_segment_points || !(s.length_m > 0.0)) continue;
      FiniteLine l;
      l.normal = rotate(s.normal);
      l.start = transform(s.start);
      l.rho = l.normal.dot(l.start);  // signed: the distance is n . q - rho either way
      l.length = s.length_m;
      l.direction = rotate((s.end - s.start) / s.length_m);
      const int id = static_cast<int>(ix.lines.size());
      ix.lines.push_back(l);
      const auto mark = [&](std::size_t b) {
        if (b < beams) ix.beam_line[b] = id;
      };
      if (s.first_beam <= s.last_beam) {
        for (std::size_t b = s.first_beam; b <= s.last_beam && b < beams; ++b) mark(b);
      } else {  // across the wrap-around of a full turn
        for (std::size_t b = s.first_beam; b < beams; ++b) mark(b);
        for (std::size_t b = 0; b <= s.last_beam && b < beams; ++b) mark(b);
      }
    }
    if (P.unsegmented_points) linkUnsegmented(scan.points, transform, rotate, P.max_distance_m, P.robust_scale_m, ix);
    for (std::size_t b = 0; b < beams; ++b) {
      const Eigen::Vector2d& p = scan.points[b];
      if (ix.beam_line[b] < 0 || !std::isfinite(p.x()) || !std::isfinite(p.y())) continue;
      const Eigen::Vector2d q = transform(p);
      ix.scratch.emplace_back(pseudoBearing(q.x(), q.y()), ix.beam_line[b]);
    }
  }
  // Scan order is bearing order up to one wrap-around: rotate, and sort only if that is not
  // enough (a scanner with an unusual layout).
  if (!ix.scratch.empty()) {
    const auto lowest = std::min_element(ix.scratch.begin(), ix.scratch.end());
    std::rotate(ix.scratch.begin(), lowest, ix.scratch.end());
    if (!std::is_sorted(ix.scratch.begin(), ix.scratch.end())) std::sort(ix.scratch.begin(), ix.scratch.end());
  }
  ix.bearing.resize(ix.scratch.size());
  ix.line_of.resize(ix.scratch.size());
  for (std::size_t k = 0; k < ix.scratch.size(); ++k) {
    ix.bearing[k] = ix.scratch[k].first;
    ix.line_of[k] = ix.scratch[k].second;
  }
  // Each place's window of 2 w entries (wrapping around), its distinct lines in the order
  // the window meets them: a line met again pairs exactly as the first time, so skipping it
  // changes nothing.
  const std::size_t n = ix.bearing.size();
  const std::size_t w = std::min(n, P.bearing_window * (ix.scans > 1 ? 2 : 1));
  ix.window = w;
  ix.window_start.resize(n + 1);
  // Grown as the lists fill (a place adds at most 2 w), so the memory follows what the lists
  // hold: a few lines per place on real scans, not the 2 w of the worst case.
  ix.window_lines.resize(std::min(n * 2 * w, 4 * n + 2 * w));
  ix.seen.assign(ix.lines.size(), -1);
  {
    const int* const line_of = ix.line_of.data();
    int* const seen = ix.seen.data();
    std::size_t used = 0;
    for (std::size_t pos = 0; pos < n; ++pos) {
      if (ix.window_lines.size() - used < 2 * w) ix.window_lines.resize(std::max(2 * ix.window_lines.size(), used + 2 * w));
      ix.window_start[pos] = static_cast<int>(used);
      int* const first = ix.window_lines.data() + used;
      int* out = first;
      std::size_t k = (pos + n - w) % n;
      for (std::size_t c = 0; c < 2 * w; ++c, k = k + 1 == n ? 0 : k + 1) {
        const int id = line_of[k];
        if (seen[id] == static_cast<int>(pos)) continue;
        seen[id] = static_cast<int>(pos);
        *out++ = id;
      }
      used += static_cast<std::size_t>(out - first);
    }
    ix.window_start[n] = static_cast<int>(used);
    ix.window_lines.resize(used);
  }
  ix.bin_start.resize(kBins + 1);
  std::size_t k = 0;
  for (int b = 0; b <= kBins; ++b) {
    const double lo = b * (4.0 / kBins);  // exact: kBins is a power of two
    while (k < ix.bearing.size() && ix.bearing[k] < lo) ++k;
    ix.bin_start[static_cast<std::size_t>(b)] = static_cast<int>(k);
  }
}

namespace {

// The signed distance of q (keyframe frame) to the nearest finite segment around its
// bearing, and that segment's normal; or, when the nearest is a lone point, the distance and
// the offset q - point with a zero normal; false when none is within max_distance_m.
// `covered` tells whether the keyframe saw a segment within about 2 degrees of the point's
// bearing: a point that could pair at all (the denominator of the inlier ratio).
bool pairPoint(const KeyframeIndex& ix, const RefinerParams& P, const Eigen::Vector2d& q,
               double& residual, Eigen::Vector2d& normal, Eigen::Vector2d& offset, bool& covered) {
  const long n = static_cast<long>(ix.bearing.size());
  covered = false;
  if (n == 0) return false;
  const double beta = pseudoBearing(q.x(), q.y());
  const int bin = std::clamp(static_cast<int>(beta * (kBins / 4.0)), 0, kBins - 1);
  long pos = ix.bin_start[static_cast<std::size_t>(bin)];
  while (pos < n && ix.bearing[static_cast<std::size_t>(pos)] < beta) ++pos;
  {
    constexpr double kCoverage = 0.025;  // pseudo-bearing units (4 per turn): 1.4 to 2.8 degrees
    const double after = ix.bearing[static_cast<std::size_t>(pos < n ? pos : 0)];
    const double before = ix.bearing[static_cast<std::size_t>(pos > 0 ? pos - 1 : n - 1)];
    const auto gap = [](double a, double b) {
      const double d = std::abs(a - b);
      return std::min(d, 4.0 - d);
    };
    covered = gap(after, beta) < kCoverage || gap(before, beta) < kCoverage;
  }
  const std::size_t place = static_cast<std::size_t>(pos < n ? pos : 0);
  const int* id = ix.window_lines.data() + ix.window_start[place];
  const int* const end = ix.window_lines.data() + ix.window_start[place + 1];
  double best = P.max_distance_m;
  bool found = false;
  for (; id != end; ++id) {
    const FiniteLine& l = ix.lines[static_cast<std::size_t>(*id)];
    if (l.length > 0.0) {
      const double d = l.normal.dot(q) - l.rho;
      if (!(std::abs(d) < best)) continue;
      const double along = (q - l.start).dot(l.direction);
      if (along < -P.endpoint_margin_m || along > l.length + P.endpoint_margin_m) continue;
      best = std::abs(d);
      residual = d;
      normal = l.normal;
    } else {  // a lone point: its two coordinates' residuals (normal left zero)
      const Eigen::Vector2d diff = q - l.start;
      const double d2 = diff.squaredNorm();
      // Most lone points are farther than the best so far: no square root for them (the
      // slack keeps the test exact: only points the root would reject are skipped).
      if (!(d2 < best * best * (1.0 + 1e-9))) continue;
      const double d = std::sqrt(d2);
      if (!(d < best)) continue;
      best = d;
      residual = d;
      offset = diff;
      normal = Eigen::Vector2d::Zero();
    }
    found = true;
  }
  return found;
}

// One point's pairing, kept between Gauss-Newton iterations: its line (normal, rho) or,
// for a lone keyframe point, that point (normal zero).
struct Pairing {
  std::uint32_t point = 0;
  Eigen::Vector2d normal = Eigen::Vector2d::Zero();
  double rho = 0.0;
  Eigen::Vector2d lone = Eigen::Vector2d::Zero();
};

// Accumulates the normal equations (yaw scaled by D(2)) and the counts at pose T in one
// pass. With `reuse` false every current point is paired anew and its pairing stored in
// `pairs`; with it true the stored pairings are used as they are (no search: the step since
// they were made is small), and `covered` is kept from the pass that made them.
void accumulate(const KeyframeIndex& ix, const RefinerParams& P, const std::vector<Eigen::Vector2d>& pts,
                const Pose2D& T, double yaw_scale, double scale, std::vector<Pairing>& pairs, bool reuse,
                Accumulator& acc, const std::vector<double>* times = nullptr) {
  const std::size_t covered = acc.covered;
  const bool store = P.reassociate_m > 0.0;
  acc = Accumulator{};
  if (reuse) acc.covered = covered;
  else pairs.clear();
  const double c = std::cos(T.yaw), s = std::sin(T.yaw);
  const double inv_c2 = 1.0 / (scale * scale);
  const double inlier_limit = 3.0 * P.robust_scale_m;
  double h[6] = {0, 0, 0, 0, 0, 0}, hu[6] = {0, 0, 0, 0, 0, 0}, g[3] = {0, 0, 0};
  const std::size_t count = reuse ? pairs.size() : pts.size();
  for (std::size_t i = 0; i < count; ++i) {
    const Eigen::Vector2d& p = pts[reuse ? pairs[i].point : i];
    const double rx = c * p.x() - s * p.y(), ry = s * p.x() + c * p.y();
    const Eigen::Vector2d q(rx + T.x, ry + T.y);
    double r = 0.0;
    Eigen::Vector2d n, offset;
    if (reuse) {
      const Pairing& pr = pairs[i];
      n = pr.normal;
      if (n.x() != 0.0 || n.y() != 0.0) {
        r = n.dot(q) - pr.rho;
      } else {
        offset = q - pr.lone;
        r = offset.norm();
      }
    } else {
      bool is_covered = false;
      const bool paired = pairPoint(ix, P, q, r, n, offset, is_covered);
      acc.covered += is_covered;
      if (!paired) continue;
      if (store) {  // only when a later iteration may reuse it (reassociate_m > 0)
        Pairing pr;
        pr.point = static_cast<std::uint32_t>(i);
        pr.normal = n;
        if (n.x() != 0.0 || n.y() != 0.0) pr.rho = n.dot(q) - r;
        else pr.lone = q - offset;
        pairs.push_back(pr);
      }
    }
    ++acc.paired;
    const double w = 1.0 / (1.0 + r * r * inv_c2);  // Cauchy, on the distance
    // One row per residual: along the line's normal, or the x and y of a point's offset.
    const double t = times != nullptr ? (*times)[reuse ? pairs[i].point : i] : 0.0;
    const auto add = [&](double nx, double ny, double ri) {
      const double turn = ny * rx - nx * ry;
      if (times != nullptr) {  // the sweep's rate: the point turns by c t about the sensor
        const double j3 = turn * t;
        acc.h3[0] += w * nx * j3, acc.h3[1] += w * ny * j3, acc.h3[2] += w * turn * yaw_scale * j3;
        acc.h33 += w * j3 * j3;
        acc.g3 += w * j3 * ri;
        acc.hu3[0] += nx * j3, acc.hu3[1] += ny * j3, acc.hu3[2] += turn * yaw_scale * j3;
        acc.hu33 += j3 * j3;
      }
      const double j0 = nx, j1 = ny, j2 = turn * yaw_scale;
      hu[0] += j0 * j0, hu[1] += j0 * j1, hu[2] += j0 * j2, hu[3] += j1 * j1, hu[4] += j1 * j2, hu[5] += j2 * j2;
      const double w0 = w * j0, w1 = w * j1, w2 = w * j2;
      h[0] += w0 * j0, h[1] += w0 * j1, h[2] += w0 * j2, h[3] += w1 * j1, h[4] += w1 * j2, h[5] += w2 * j2;
      g[0] += w0 * ri, g[1] += w1 * ri, g[2] += w2 * ri;
    };
    if (n.x() != 0.0 || n.y() != 0.0) {
      add(n.x(), n.y(), r);
    } else {
      add(1.0, 0.0, offset.x());
      add(0.0, 1.0, offset.y());
    }
    acc.wr2 += w * r * r;
    acc.wsum += w;
    if (std::abs(r) < inlier_limit) {
      ++acc.inliers;
      acc.inlier_r2 += r * r;
    }
  }
  acc.H << h[0], h[1], h[2], h[1], h[3], h[4], h[2], h[4], h[5];
  acc.Hu << hu[0], hu[1], hu[2], hu[1], hu[3], hu[4], hu[2], hu[4], hu[5];
  acc.g << g[0], g[1], g[2];
}

}  // namespace

const char* toString(RefineStatus s) {
  switch (s) {
    case RefineStatus::kOk:
      return "ok";
    case RefineStatus::kDegenerate:
      return "degenerate";
    case RefineStatus::kFailed:
      return "failed";
  }
  return "unknown";
}

void RefinerParams::validate() const {
  if (static_cast<std::size_t>(level) >= kNumCascadeLevels) {
    detail::failKey("level", "a cascade level 0..3", static_cast<double>(static_cast<std::size_t>(level)));
  }
  if (min_segment_points < 2) detail::failKey("min_segment_points", ">= 2", static_cast<double>(min_segment_points));
  // Counts that drive the work of one refinement are bounded (issue 16).
  if (max_iterations < 1 || max_iterations > kMaxIterations) {
    detail::failKey("max_iterations", "in [1, 1000]", static_cast<double>(max_iterations));
  }
  detail::requirePositive("max_distance_m", max_distance_m);
  detail::requirePositive("robust_scale_m", robust_scale_m);
  detail::requireNonNegative("initial_scale_m", initial_scale_m);  // beyond max_distance_m: that is used
  detail::requireNonNegative("endpoint_margin_m", endpoint_margin_m);
  if (bearing_window < 1 || bearing_window > 64) {
    detail::failKey("bearing_window", "in [1, 64]", static_cast<double>(bearing_window));
  }
  detail::requireSigmaM("min_point_sigma_m", min_point_sigma_m, false);
  detail::requireSigmaM("model_sigma_m", model_sigma_m, true);
  detail::requireSigmaRad("model_sigma_rad", model_sigma_rad, true);
  detail::requireInRange("correlation_length_points", correlation_length_points, 1.0, 1e3);
  detail::requireInRange("min_inlier_ratio", min_inlier_ratio, 0.0, 1.0);
  if (min_points < 3) detail::failKey("min_points", ">= 3", static_cast<double>(min_points));
  detail::requireInRange("degeneracy_ratio", degeneracy_ratio, 0.0, 1.0);
  detail::requireNonNegative("min_constraint_points", min_constraint_points);
  detail::requireSigmaM("unconstrained_sigma_m", unconstrained_sigma_m, false);
  detail::requirePositive("convergence_m", convergence_m);
  detail::requireNonNegative("reassociate_m", reassociate_m);
  if (max_points < min_points) detail::failKey("max_points", ">= min_points", static_cast<double>(max_points));
  if (max_points > kMaxPoints) detail::failKey("max_points", "<= 100000", static_cast<double>(max_points));
}

ScanRefiner::ScanRefiner(const RefinerParams& params) : params_(params) { params_.validate(); }

namespace {
// The valid points, evenly thinned to at most `limit`.
// With `times` (per beam), the kept points' times go to `out_times`.
void collectPoints(const Segmentation& current, std::size_t limit, std::vector<Eigen::Vector2d>& out,
                   const std::vector<double>* times = nullptr, std::vector<double>* out_times = nullptr) {
  out.clear();
  if (out_times != nullptr) out_times->clear();
  std::size_t valid = 0;
  for (const Eigen::Vector2d& p : current.points) valid += std::isfinite(p.x()) && std::isfinite(p.y());
  const double stride = std::max(1.0, static_cast<double>(valid) / static_cast<double>(limit));
  double next = 0.0;
  std::size_t k = 0;
  for (std::size_t b = 0; b < current.points.size(); ++b) {
    const Eigen::Vector2d& p = current.points[b];
    if (!(std::isfinite(p.x()) && std::isfinite(p.y()))) continue;
    if (static_cast<double>(k++) >= next) {
      out.push_back(p);
      if (out_times != nullptr) out_times->push_back((*times)[b]);
      next += stride;
    }
  }
}
}  // namespace

RefineResult ScanRefiner::refine(const Segmentation& keyframe, const Segmentation& current,
                                 const Pose2D& initial) const {
  thread_local RefinementKeyframe prepared;
  prepare(keyframe, prepared);
  return refine(prepared, current, initial);
}

RefineResult ScanRefiner::refine(const RefinementKeyframe& keyframe, const Segmentation& current,
                                 const Pose2D& initial) const {
  return refine(keyframe, current, initial, nullptr);
}

RefineResult ScanRefiner::refine(const RefinementKeyframe& keyframe, const Segmentation& current,
                                 const Pose2D& initial, const SweepModel* sweep, bool guessed_start) const {
  const RefinerParams& P = params_;
  RefineResult result;
  result.T_key_curr = initial;
  const double u2 = P.unconstrained_sigma_m * P.unconstrained_sigma_m;
  result.covariance = Eigen::Vector3d(u2, u2, 0.1).asDiagonal();
  // A non-finite start pairs nothing (its bearings would be undefined): failed.
  if (!(std::isfinite(initial.x) && std::isfinite(initial.y) && std::isfinite(initial.yaw))) return result;
  const bool sweeping = sweep != nullptr && sweep->time_offsets_s != nullptr &&
                        sweep->time_offsets_s->size() == current.points.size() && sweep->prior_sigma_rad_s > 0.0;
  thread_local std::vector<Eigen::Vector2d> points, turned;
  thread_local std::vector<double> times;
  collectPoints(current, P.max_points, points, sweeping ? sweep->time_offsets_s : nullptr, sweeping ? &times : nullptr);
  result.points = points.size();
  if (points.size() < P.min_points || keyframe.bearing.empty()) return result;

  // Yaw is scaled by the points' RMS range so that the information is compared in metres.
  double sum_r2 = 0.0;
  for (const Eigen::Vector2d& p : points) sum_r2 += p.squaredNorm();
  const double L = std::max(0.1, std::sqrt(sum_r2 / static_cast<double>(points.size())));
  const Eigen::Vector3d D(1.0, 1.0, 1.0 / L);
  result.rms_range_m = L;

  Pose2D T = initial;
  Accumulator acc;
  Eigen::Matrix3d V = Eigen::Matrix3d::Identity();
  Eigen::Vector3d strong_mask = Eigen::Vector3d::Ones();
  bool degenerate = false;
  // Which directions are constrained is decided on the unweighted information: a jamb's
  // points, far from their line at the start, have small robust weights but still count.
  const auto decompose = [&](const Eigen::Matrix3d& Hu) {
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(Hu);
    const Eigen::Vector3d lambda = eig.eigenvalues();  // ascending
    V = eig.eigenvectors();
    degenerate = false;
    for (int k = 0; k < 3; ++k) {
      strong_mask(k) = lambda(k) > std::max(P.degeneracy_ratio * lambda(2), P.min_constraint_points) ? 1.0 : 0.0;
      degenerate = degenerate || strong_mask(k) == 0.0;
    }
    return lambda(2) > 0.0 && strong_mask.sum() > 0.0;
  };
  const auto strongBasis = [&]() {
    Basis Vs(3, static_cast<Eigen::Index>(strong_mask.sum()));
    Eigen::Index c = 0;
    for (int k = 0; k < 3; ++k) {
      if (strong_mask(k) != 0.0) Vs.col(c++) = V.col(k);
    }
    return Vs;
  };

  // Each iteration pairs the points at T, solves, and steps; the statistics come from the
  // last pairing (the final step is below convergence_m, or the iterations ran out).
  thread_local std::vector<Pairing> pairs;
  bool reuse = false;
  // The sweep's rate correction c (rad/s) and its prior's weight in the normal equations'
  // units (a point's variance, as the covariance below counts it, over the rate's).
  double c = 0.0;
  bool at_bound = false;  // c held at its bound: the pose is then solved with c fixed
  const double lambda = sweeping ? P.min_point_sigma_m * P.min_point_sigma_m * P.correlation_length_points /
                                       (sweep->prior_sigma_rad_s * sweep->prior_sigma_rad_s)
                                 : 0.0;
  double t_max = 0.0;
  if (sweeping) {
    for (double t : times) t_max = std::max(t_max, std::abs(t));
  } else {
    times.clear();
  }
  Eigen::Matrix3d H_pose;  // the pose's information, the rate eliminated (Schur complement)
  Eigen::Vector3d g_pose;
  // The loss's scale this iteration: from initial_scale_m, halved each iteration down to
  // robust_scale_m (graduated robustness).
  double scale =
      guessed_start ? std::max(P.robust_scale_m, std::min(P.initial_scale_m, P.max_distance_m)) : P.robust_scale_m;
  for (std::size_t it = 0; it < P.max_iterations; ++it) {
    if (sweeping) {
      // The points turned by c t about the sensor (exact rotation: c t reaches 0.3 rad).
      turned.resize(points.size());
      for (std::size_t i = 0; i < points.size(); ++i) {
        const double a = c * times[i], ca = std::cos(a), sa = std::sin(a);
        const Eigen::Vector2d& p = points[i];
        turned[i] = Eigen::Vector2d(ca * p.x() - sa * p.y(), sa * p.x() + ca * p.y());
      }
    }
    accumulate(keyframe, P, sweeping ? turned : points, T, D(2), scale, pairs, reuse, acc, sweeping ? &times : nullptr);
    // With the sweep's rate unknown too, what constrains the pose is what the rate does not
    // explain: the directions are judged on the unweighted information with the rate
    // eliminated (a corridor's along-axis cue may be spent on bending its walls).
    Eigen::Matrix3d Hu = acc.Hu;
    if (sweeping) {
      const Eigen::Vector3d hu3(acc.hu3[0], acc.hu3[1], acc.hu3[2]);
      Hu -= hu3 * hu3.transpose() / (acc.hu33 + lambda);
    }
    if (acc.paired < P.min_points || !decompose(Hu)) return result;
    H_pose = acc.H;
    g_pose = acc.g;
    Eigen::Vector3d h3 = Eigen::Vector3d::Zero();
    double s33 = 1.0, g3 = 0.0;
    if (sweeping) {
      h3 = Eigen::Vector3d(acc.h3[0], acc.h3[1], acc.h3[2]);
      s33 = acc.h33 + lambda;
      g3 = acc.g3 + lambda * c;
      H_pose -= h3 * h3.transpose() / s33;
      g_pose -= h3 * (g3 / s33);
    }
    // Step in the constrained subspace only (the weak directions keep their value).
    const Basis Vs = strongBasis();
    const Reduced Hs = Vs.transpose() * H_pose * Vs;
    Eigen::Vector3d step = -Vs * Hs.ldlt().solve(Vs.transpose() * g_pose);
    if (!step.allFinite()) return result;
    double dc = 0.0;
    at_bound = false;
    if (sweeping) {
      // Within 3 prior sigmas: beyond, a corridor's points fit as well turned by a quarter
      // or a half turn at the sweep's end (the pose then flips), which no robot does.
      const double bound = 3.0 * sweep->prior_sigma_rad_s;
      dc = -(g3 + h3.dot(step)) / s33;
      if (!std::isfinite(dc)) return result;
      const double held = std::clamp(c + dc, -bound, bound) - c;
      if (held != dc) {
        // The rate is held: the pose's step for that rate, not for the one the reduced
        // system assumed (its gradient moves with the rate through the coupling h3).
        at_bound = true;
        dc = held;
        H_pose = acc.H;
        g_pose = acc.g + h3 * dc;
        const Reduced Hf = Vs.transpose() * H_pose * Vs;
        step = -Vs * Hf.ldlt().solve(Vs.transpose() * g_pose);
        if (!step.allFinite()) return result;
      }
      c += dc;
    }
    step = step.cwiseProduct(D);  // back to (m, m, rad)
    T.x += step.x();
    T.y += step.y();
    T.yaw = wrapAngle(T.yaw + step.z());
    result.iterations = it + 1;
    const double moved = std::max({std::hypot(step.x(), step.y()), std::abs(step.z()) * L, std::abs(dc) * t_max * L});
    const bool final_scale = scale <= P.robust_scale_m;
    scale = std::max(P.robust_scale_m, 0.5 * scale);
    if (moved < P.convergence_m) {
      if (!final_scale) {
        scale = P.robust_scale_m;  // at rest under a wider loss: the final loss's iterations follow
        reuse = false;
        continue;
      }
      result.converged = true;
      break;
    }
    // Small steps keep the pairings (the points move by less than reassociate_m).
    reuse = moved < P.reassociate_m;
  }
  result.T_key_curr = T;
  result.sweep_rate_correction = c;
  result.inliers = acc.inliers;
  result.covered = acc.covered;
  result.inlier_ratio = inlierRatioOf(acc);
  result.rms_m = acc.inliers > 0 ? std::sqrt(acc.inlier_r2 / static_cast<double>(acc.inliers)) : 0.0;
  // Residual variance (robustly weighted), floored; information of correlated points shared.
  const double dof = std::max(1.0, acc.wsum - (sweeping && !at_bound ? 4.0 : 3.0));
  const double sigma2 = std::max(acc.wr2 / dof, P.min_point_sigma_m * P.min_point_sigma_m);
  const Basis Vs = strongBasis();
  const Reduced Hs = Vs.transpose() * H_pose * Vs;
  Eigen::Matrix3d cov_scaled = Vs * Hs.inverse() * Vs.transpose() * (sigma2 * P.correlation_length_points);
  for (int k = 0; k < 3; ++k) {
    if (strong_mask(k) == 0.0) cov_scaled += V.col(k) * V.col(k).transpose() * u2;
  }
  result.covariance = D.asDiagonal() * cov_scaled * D.asDiagonal();
  // Model error no residual shows: the keyframe's own distortion (deskewed with an estimated
  // velocity), its segments' fit; a floor on each standard deviation.
  result.covariance(0, 0) += P.model_sigma_m * P.model_sigma_m;
  result.covariance(1, 1) += P.model_sigma_m * P.model_sigma_m;
  result.covariance(2, 2) += P.model_sigma_rad * P.model_sigma_rad;
  if (degenerate) {
    const Eigen::Vector2d t = V.col(0).head<2>();
    result.degenerate_direction = t.norm() > 1e-9 ? Eigen::Vector2d(t.normalized()) : Eigen::Vector2d::Zero();
  }
  if (result.inliers < P.min_points || result.inlier_ratio < P.min_inlier_ratio) {
    result.status = RefineStatus::kFailed;
    return result;
  }
  result.status = degenerate ? RefineStatus::kDegenerate : RefineStatus::kOk;
  return result;
}

}  // namespace lidarseg
