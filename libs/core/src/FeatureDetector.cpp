#include "lidarseg/core/FeatureDetector.h"
#include "lidarseg/core/Angles.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/LU>

#include "Validation.h"

namespace lidarseg {

namespace {

// Covariance of a door (x, y, theta) on the wall line (rho, theta) with normal `normal` and
// tangent `tangent`, at abscissa `s_along` on it: the wall's (rho, theta) covariance
// `wall_cov` and the jambs' position variances `var_a`, `var_b` along the wall (the centre
// is their mean), through the Jacobian of (x, y, theta) with respect to (rho, theta, s).
Eigen::Matrix3d doorCovariance(const Eigen::Vector2d& normal, double rho, const Eigen::Vector2d& tangent,
                               double s_along, const Eigen::Matrix2d& wall_cov, double var_a, double var_b) {
  Eigen::Matrix3d J = Eigen::Matrix3d::Zero();
  J.block<2, 1>(0, 0) = normal;
  J.block<2, 1>(0, 1) = rho * tangent - s_along * normal;
  J.block<2, 1>(0, 2) = tangent;
  J(2, 1) = 1.0;
  Eigen::Matrix3d S = Eigen::Matrix3d::Zero();
  S.topLeftCorner<2, 2>() = wall_cov;
  S(2, 2) = 0.25 * (var_a + var_b);
  return J * S * J.transpose();
}


double cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.x() * b.y() - a.y() * b.x(); }

// Tangent of a segment's line: d(normal)/d(theta), the normal turned by +90 degrees.
Eigen::Vector2d tangentOf(const Segment& s) { return {-s.normal.y(), s.normal.x()}; }

// A jamb: the end of a wall segment next to a gap. The true end of the wall lies between
// the wall's last point and the point where the first beam of the gap crosses the wall's
// line; the estimate is the middle, its along-line variance that of a uniform spread over
// the interval plus the range noise.
struct Jamb {
  Eigen::Vector2d point;
  double variance_m2;
};

Jamb jambOf(const Segment& wall, const Eigen::Vector2d& wall_end, const Eigen::Vector2d& gap_point) {
  const double spacing_mean = wall.num_points > 1 ? wall.length_m / (wall.num_points - 1) : wall.length_m;
  Jamb j{wall_end, spacing_mean * spacing_mean / 12.0 + wall.covariance(0, 0)};
  const double r = gap_point.norm();
  if (!std::isfinite(r) || r <= 0.0) return j;
  const Eigen::Vector2d u = gap_point / r;
  const double nu = wall.normal.dot(u);
  if (nu <= 1e-6) return j;
  const Eigen::Vector2d crossing = (wall.rho_m / nu) * u;
  const double spacing = (crossing - wall_end).norm();
  if (spacing > 4.0 * spacing_mean + 0.05) return j;  // the beam is too far off: keep the point
  j.point = 0.5 * (wall_end + crossing);
  j.variance_m2 = spacing * spacing / 12.0 + wall.covariance(0, 0);
  return j;
}

// Spacing along a wall with unit normal `normal` between neighbouring beams `step` apart
// around the point q on it: r * step / cos(incidence) (infinite at 90 degrees).
double beamSpacing(const Eigen::Vector2d& q, const Eigen::Vector2d& normal, double step) {
  const double r = q.norm();
  const double c = r > 0.0 ? std::abs(normal.dot(q)) / r : 0.0;
  return c > 1e-6 ? r * step / c : std::numeric_limits<double>::infinity();
}

// Cosine of the incidence on a wall with unit normal `normal` at its point q.
double incidenceCos(const Eigen::Vector2d& q, const Eigen::Vector2d& normal) {
  const double r = q.norm();
  return r > 0.0 ? std::abs(normal.dot(q)) / r : 1.0;
}

// The tolerance of q's distance from the line of `a` when q is the end of `b`: the wall's
// allowance (flatness, and the placement of an end between two beams) plus door_noise_sigmas
// standard deviations of the range noise `sigma` seen at that incidence (a range error moves
// a point along its beam, so across the wall by cos(incidence) of it). The fits' own
// uncertainty is left out on purpose: a far, short wall whose line is unsure is no evidence
// that two pieces are one wall, so it must not widen the test.
double collinearToleranceOf(const FeatureDetectorParams& p, double sigma, const Segment& a, const Eigen::Vector2d& q) {
  return p.door_collinear_offset_m + p.door_noise_sigmas * sigma * incidenceCos(q, a.normal);
}

// Whether q lies within that tolerance of a's line; the incidence (a square root) is only
// computed when the distance falls between the tolerance's bounds (cos in [0, 1]).
bool onLineOf(const FeatureDetectorParams& p, double sigma, const Segment& a, const Eigen::Vector2d& q) {
  const double d = std::abs(a.signedDistance(q));
  if (d <= p.door_collinear_offset_m) return true;
  if (d > p.door_collinear_offset_m + p.door_noise_sigmas * sigma) return false;
  return d <= collinearToleranceOf(p, sigma, a, q);
}

// std::lround(v) without the library call, for the ranges in millimetres: below 2^52 a
// non-negative double's truncation is exact and so is its fractional part, so a half rounds
// up (away from zero) exactly as std::lround does; anything else goes to std::lround.
long roundRangeMm(double v) {
  if (!(v >= 0.0 && v < 4503599627370496.0)) return std::lround(v);
  const long whole = static_cast<long>(v);
  return v - static_cast<double>(whole) >= 0.5 ? whole + 1 : whole;
}

// Segment::signedDistance (normal . q - rho) inlined for the per-beam loops: the same
// expression, so the same value; the member function lives in another translation unit.
double distanceBehind(const Segment& s, const Eigen::Vector2d& q) { return s.normal.dot(q) - s.rho_m; }

// The grids rangeQuantum tries (mm; each divides 100 mm), and the largest quantum it can
// return, computed as it computes it.
constexpr int kRangeGridsMm[4] = {10, 20, 50, 100};
constexpr double kMaxRangeQuantum = kRangeGridsMm[3] * 1e-3;

std::size_t beamsBetween(std::uint32_t last_of_a, std::uint32_t first_of_b, std::size_t num_beams) {
  // Beams strictly after last_of_a and strictly before first_of_b, in scan order (wrapping).
  const std::size_t n = num_beams;
  const std::size_t from = (last_of_a + 1) % n;
  return (first_of_b + n - from) % n;
}

}  // namespace

void FeatureDetectorParams::validate() const {
  using detail::failKey;
  using detail::requireInRange;
  using detail::requireNonNegative;
  using detail::requirePositive;
  if (static_cast<std::size_t>(level) >= kNumCascadeLevels) {
    failKey("level", "a cascade level 0..3", static_cast<double>(level));
  }
  requirePositive("corner_max_gap_m", corner_max_gap_m);
  requireInRange("corner_min_angle_deg", corner_min_angle_deg, 1.0, 179.0);
  requireInRange("corner_max_angle_deg", corner_max_angle_deg, 1.0, 179.0);
  if (corner_max_angle_deg < corner_min_angle_deg) {
    failKey("corner_max_angle_deg", ">= corner_min_angle_deg", corner_max_angle_deg);
  }
  requireNonNegative("corner_min_arm_m", corner_min_arm_m);
  if (corner_min_points < 2) failKey("corner_min_points", ">= 2", static_cast<double>(corner_min_points));
  requirePositive("door_min_width_m", door_min_width_m);
  requirePositive("door_max_width_m", door_max_width_m);
  if (door_max_width_m < door_min_width_m) failKey("door_max_width_m", ">= door_min_width_m", door_max_width_m);
  requireInRange("door_collinear_angle_deg", door_collinear_angle_deg, 0.0, 45.0);
  requireNonNegative("door_collinear_offset_m", door_collinear_offset_m);
  requireInRange("door_noise_sigmas", door_noise_sigmas, 0.0, 20.0);
  detail::requireSigmaM("door_min_range_sigma_m", door_min_range_sigma_m, false);
  requireInRange("door_gap_min_spacings", door_gap_min_spacings, 0.0, 100.0);
  requireInRange("door_quantum_min_share", door_quantum_min_share, 0.0, 1.0);
  if (door_quantum_min_share <= 0.2) {
    // Centimetre ranges fall on a 5 cm grid's best class by chance one time in five or more.
    failKey("door_quantum_min_share", "> 0.2", door_quantum_min_share);
  }
  requireNonNegative("door_min_wall_m", door_min_wall_m);
  if (door_min_wall_points < 2) {
    failKey("door_min_wall_points", ">= 2", static_cast<double>(door_min_wall_points));
  }
  if (door_min_sparse_wall_points < 2 || door_min_sparse_wall_points > door_min_wall_points) {
    failKey("door_min_sparse_wall_points", "in [2, door_min_wall_points]", static_cast<double>(door_min_sparse_wall_points));
  }
  if (door_min_gap_beams < 1) failKey("door_min_gap_beams", ">= 1", static_cast<double>(door_min_gap_beams));
  requireNonNegative("door_front_tolerance_m", door_front_tolerance_m);
  requireInRange("door_max_occluded_fraction", door_max_occluded_fraction, 0.0, 1.0);
  requireInRange("door_min_beyond_fraction", door_min_beyond_fraction, 0.0, 1.0);
  requireNonNegative("door_min_recess_m", door_min_recess_m);
  requirePositive("door_max_recess_m", door_max_recess_m);
  if (door_max_recess_m <= door_min_recess_m) {
    failKey("door_max_recess_m", "> door_min_recess_m", door_max_recess_m);
  }
  requireInRange("door_leaf_parallel_deg", door_leaf_parallel_deg, 0.0, 45.0);
  requireInRange("door_min_leaf_fraction", door_min_leaf_fraction, 0.0, 1.0);
  requireNonNegative("door_min_ajar_leaf_m", door_min_ajar_leaf_m);
  requirePositive("door_hinge_tolerance_m", door_hinge_tolerance_m);
  requireNonNegative("door_reveal_tolerance_m", door_reveal_tolerance_m);
  if (door_shallow_window < 2 || door_shallow_window > 100) {
    failKey("door_shallow_window", "2..100", static_cast<double>(door_shallow_window));
  }
  requireNonNegative("door_shallow_min_sigmas", door_shallow_min_sigmas);
  if (!(door_shallow_max_recess_m > door_min_recess_m && door_shallow_max_recess_m <= door_max_recess_m)) {
    failKey("door_shallow_max_recess_m", "in (door_min_recess_m, door_max_recess_m]", door_shallow_max_recess_m);
  }
  if (!(door_shallow_min_recess_m > 0.0 && door_shallow_min_recess_m < door_shallow_max_recess_m)) {
    failKey("door_shallow_min_recess_m", "in (0, door_shallow_max_recess_m)", door_shallow_min_recess_m);
  }
  requireInRange("door_shallow_max_incidence_deg", door_shallow_max_incidence_deg, 0.0, 90.0);
  requireNonNegative("corner_door_exclusion_m", corner_door_exclusion_m);
  if (door_max_segments_between > 1000) {
    failKey("door_max_segments_between", "<= 1000", static_cast<double>(door_max_segments_between));
  }
}

FeatureDetector::FeatureDetector(const FeatureDetectorParams& params) : params_(params) {
  params_.validate();
  cos_collinear_ = std::cos(params_.door_collinear_angle_deg * kDegToRad);
  sin_leaf_parallel_ = std::sin(params_.door_leaf_parallel_deg * kDegToRad);
  cos_corner_min_ = std::cos(params_.corner_min_angle_deg * kDegToRad);
  cos_corner_max_ = std::cos(params_.corner_max_angle_deg * kDegToRad);
  cos_shallow_incidence_ = std::cos(params_.door_shallow_max_incidence_deg * kDegToRad);
}

std::vector<Feature> FeatureDetector::detect(const Segmentation& segmentation) const {
  std::vector<Feature> out;
  detect(segmentation, out);
  return out;
}

void FeatureDetector::detect(const Segmentation& segmentation, std::vector<Feature>& out) const {
  out.clear();
  if (segmentation.points.empty()) return;
  const ScanGeometry geometry = measure(segmentation);
  detectDoors(segmentation, geometry, out);
  detectShallowDoors(segmentation, geometry, out);
  detectCorners(segmentation, out);
}

FeatureDetector::ScanGeometry FeatureDetector::measure(const Segmentation& segmentation) const {
  ScanGeometry g;
  const std::vector<Eigen::Vector2d>& pts = segmentation.points;
  // The beam step: the median angle between the first (up to) 9 pairs of neighbouring
  // valid beams (exact without bearing noise; the median ignores a pair across a gap).
  double steps[9];
  std::size_t num_steps = 0;
  for (std::size_t i = 0; i + 1 < pts.size() && num_steps < 9; ++i) {
    const Eigen::Vector2d &u = pts[i], &v = pts[i + 1];
    if (!std::isfinite(u.x()) || !std::isfinite(v.x())) continue;
    const double step = std::abs(std::atan2(cross(u, v), u.dot(v)));
    if (step > 0.0) steps[num_steps++] = step;
  }
  if (num_steps > 0) {
    std::nth_element(steps, steps + num_steps / 2, steps + num_steps);
    g.beam_step_rad = steps[num_steps / 2];
  }
  // The range noise: each raw wall of at least 10 points gives RSS / sum(cos^2 incidence)
  // (a range error dr moves a point by dr cos(incidence) off its line; cos = rho / r, so the
  // sum is rho^2 * sum(1 / r^2), a moment the fit keeps), corrected for the 2 fitted
  // parameters; the median over the walls ignores the ones bent at a leaf or a corner.
  thread_local std::vector<double> tl_sigmas;
  std::vector<double>& sigmas = tl_sigmas;
  sigmas.clear();
  for (const Segment& s : segmentation.level(CascadeLevel::kWallDanielsson).segments) {
    if (s.num_points < 10) continue;
    const double cos2 = s.rho_m * s.rho_m * s.moments.sum_w;
    if (!(cos2 > 1e-6)) continue;
    const double n = static_cast<double>(s.num_points);
    sigmas.push_back(s.residual_ss_m2 / cos2 * n / (n - 2.0));
  }
  double var = params_.door_min_range_sigma_m * params_.door_min_range_sigma_m;
  if (sigmas.size() >= 3) {
    std::nth_element(sigmas.begin(), sigmas.begin() + sigmas.size() / 2, sigmas.end());
    var = std::max(var, sigmas[sigmas.size() / 2]);
  }
  g.range_sigma_m = std::sqrt(var);
  return g;
}

double FeatureDetector::rangeQuantum(const Segmentation& segmentation, std::size_t first_beam, std::size_t count) const {
  const std::vector<Eigen::Vector2d>& pts = segmentation.points;
  const std::size_t num_beams = pts.size();
  if (num_beams == 0) return 0.0;
  // Residues of the ranges in millimetres modulo 10 cm; every grid tried divides 10 cm.
  std::uint32_t hist[100] = {};
  std::size_t n = 0;
  for (std::size_t c = 0, beam = first_beam % num_beams; c < count && c < num_beams;
       ++c, beam = beam + 1 == num_beams ? 0 : beam + 1) {
    const Eigen::Vector2d& q = pts[beam];
    if (!std::isfinite(q.x())) continue;
    const long mm = roundRangeMm(q.norm() * 1000.0);
    // (A range is never negative: its class is an unsigned remainder, cheaper than the
    // signed one; the signed expression is kept for whatever std::lround gives a NaN.)
    ++hist[mm >= 0 ? static_cast<std::size_t>(mm) % 100 : static_cast<std::size_t>(((mm % 100) + 100) % 100)];
    ++n;
  }
  if (n < 8) return 0.0;
  // Share of the ranges on the best grid of each step (any offset). The counts on each
  // offset of the 50, 20 and 10 mm grids are folded from the 100 mm histogram (integer sums:
  // the same counts as summing every tenth, fifth or second class).
  const int* const grids = kRangeGridsMm;
  std::uint32_t on50[50], on20[20], on10[10];
  for (int o = 0; o < 50; ++o) on50[o] = hist[o] + hist[o + 50];
  for (int o = 0; o < 20; ++o) on20[o] = hist[o] + hist[o + 20] + hist[o + 40] + hist[o + 60] + hist[o + 80];
  for (int o = 0; o < 10; ++o) on10[o] = on20[o] + on20[o + 10];
  const std::uint32_t best[4] = {*std::max_element(on10, on10 + 10), *std::max_element(on20, on20 + 20),
                                 *std::max_element(on50, on50 + 50), *std::max_element(hist, hist + 100)};
  double share[4];
  for (int g = 0; g < 4; ++g) share[g] = static_cast<double>(best[g]) / static_cast<double>(n);
  // The largest step holding door_quantum_min_share of the ranges and nearly (80 %) as many
  // as each finer step that divides it: ranges on a 5 cm grid put half of them on each of
  // two 10 cm grids, which is no 10 cm grid.
  for (int g = 3; g >= 0; --g) {
    if (share[g] < params_.door_quantum_min_share) continue;
    bool coarse = true;
    for (int d = 0; d < g; ++d) coarse = coarse && (grids[g] % grids[d] != 0 || share[g] >= 0.8 * share[d]);
    if (coarse) return grids[g] * 1e-3;
  }
  return 0.0;
}

void FeatureDetector::detectDoors(const Segmentation& segmentation, const ScanGeometry& geometry,
                                  std::vector<Feature>& out) const {
  const FeatureDetectorParams& p = params_;
  const std::vector<Segment>& segs = segmentation.level(params_.level).segments;
  const std::size_t n = segs.size();
  const std::size_t num_beams = segmentation.points.size();
  const bool wraps = segmentation.wraps_around;
  const double step = geometry.beam_step_rad;
  const double sigma = geometry.range_sigma_m;
  // A wall beside a door: door_min_wall_m long, with door_min_wall_points points or as many
  // as the beams can leave on that length where it is (sparse at range and grazing
  // incidence), but at least door_min_sparse_wall_points.
  auto wallOk = [&](const Segment& s) {
    if (s.length_m < p.door_min_wall_m || s.num_points < p.door_min_sparse_wall_points) return false;
    if (s.num_points >= p.door_min_wall_points) return true;
    if (step <= 0.0) return false;
    const double spacing = beamSpacing(s.cog, s.normal, step);
    return static_cast<double>(s.num_points) >= std::min<double>(static_cast<double>(p.door_min_wall_points),
                                                                    1.0 + std::floor(p.door_min_wall_m / spacing));
  };
  for (std::size_t i = 0; i < n; ++i) {
    const Segment& a = segs[i];
    if (!wallOk(a)) continue;
    const Eigen::Vector2d t = a.direction();
    for (std::size_t k = 1; k <= p.door_max_segments_between + 1; ++k) {
      std::size_t j = i + k;
      if (j >= n) {
        if (!wraps) break;
        j -= n;
        if (j >= i) break;
      }
      const Segment& b = segs[j];
      if (a.normal.dot(b.normal) < cos_collinear_) continue;
      if (!onLineOf(p, sigma, a, b.start) || !onLineOf(p, sigma, b, a.end)) {
        continue;
      }
      const Eigen::Vector2d gap0 = b.start - a.end;
      if (gap0.dot(t) <= 0.0) continue;
      // Jambs refined with the first and last beams of the gap.
      Jamb jamb_a = jambOf(a, a.end, segmentation.points[(a.last_beam + 1) % num_beams]);
      Jamb jamb_b = jambOf(b, b.start, segmentation.points[(b.first_beam + num_beams - 1) % num_beams]);
      const double width = (jamb_b.point - jamb_a.point).norm();
      if (width < p.door_min_width_m) continue;  // a recessed leaf or a broken wall: look further
      if (width > p.door_max_width_m) break;     // further segments are only further away
      if (!wallOk(b)) break;

      // The beams of the gap: where do they end relative to the wall line? Those on a
      // reveal (the far side of the opening through a thick wall, seen obliquely) are the
      // frame, not the doorway.
      const std::size_t count = beamsBetween(a.last_beam, b.first_beam, num_beams);
      if (count < p.door_min_gap_beams) break;
      // Sparse sampling is no opening: the gap must be door_gap_min_spacings beam spacings
      // wide at both jambs (the spacing grows with range and with incidence).
      if (step > 0.0 && width < p.door_gap_min_spacings * std::max(beamSpacing(jamb_a.point, a.normal, step),
                                                                   beamSpacing(jamb_b.point, a.normal, step))) {
        break;
      }
      // A reveal runs straight back from a jamb, which lies between the wall's last point
      // and one beam spacing into the gap: along the wall, within that interval (plus the
      // tolerance) of a wall's end.
      const double s_jamb_a = jamb_a.point.dot(t), s_jamb_b = jamb_b.point.dot(t);
      const double s_end_a = a.end.dot(t), s_start_b = b.start.dot(t);
      const double spacing_a = a.num_points > 1 ? a.length_m / (a.num_points - 1) : 0.0;
      const double spacing_b = b.num_points > 1 ? b.length_m / (b.num_points - 1) : 0.0;
      const double tol = p.door_reveal_tolerance_m;
      // A reveal faces the opening, so the sensor (the origin) sees jamb a's only from b's
      // side of it and jamb b's only from a's side (both from in front of the doorway).
      const bool see_reveal_a = s_jamb_a <= tol, see_reveal_b = s_jamb_b >= -tol;
      // 1: on jamb a's reveal, 2: on jamb b's, 0: on neither.
      auto revealOf = [&](const Eigen::Vector2d& q) {
        const double depth = distanceBehind(a, q);
        if (depth < -tol || depth > p.door_max_recess_m + tol) return 0;
        const double s = q.dot(t);
        if (see_reveal_a && s >= s_end_a - tol && s <= s_end_a + spacing_a + tol) return 1;
        if (see_reveal_b && s >= s_start_b - spacing_b - tol && s <= s_start_b + tol) return 2;
        return 0;
      };
      auto onReveal = [&](const Eigen::Vector2d& q) { return revealOf(q) != 0; };
      std::size_t front = 0, beyond = 0, reveal = 0, seen_beyond = 0;
      std::size_t beam = (a.last_beam + 1) % num_beams;
      for (std::size_t c = 0; c < count; ++c, beam = (beam + 1) % num_beams) {
        const Eigen::Vector2d& q = segmentation.points[beam];
        if (!std::isfinite(q.x())) {
          ++beyond;  // no return: nothing stopped the beam in the doorway (or it was lost)
          continue;
        }
        const double d = distanceBehind(a, q);
        if (onReveal(q)) {
          ++reveal;
        } else if (d < -p.door_front_tolerance_m) {
          ++front;
        } else if (d > p.door_max_recess_m) {
          ++beyond;
          ++seen_beyond;
        }
      }
      // Shares are of the doorway's beams (at a grazing angle, the reveal may take most).
      const double total = static_cast<double>(std::max<std::size_t>(1, count - reveal));
      if (static_cast<double>(front) > p.door_max_occluded_fraction * total) break;

      // Segments inside the gap: a recessed leaf (closed) or a turned leaf (ajar). Ranges on
      // a grid of step q make staircases q cos(incidence) deep on a plain wall, and add
      // q^2 / 12 to the range variance: looked for over the gap and a few points each side.
      // Measured only when a segment in the gap needs it (most gaps hold none).
      const std::size_t side = 8;
      const double cos_gap = incidenceCos(0.5 * (jamb_a.point + jamb_b.point), a.normal);
      double quantum = -1.0;
      auto quantumHere = [&] {
        if (quantum < 0.0) {
          quantum = rangeQuantum(segmentation, (a.last_beam + num_beams + 1 - std::min<std::size_t>(side, a.num_points)) % num_beams,
                                 count + 2 * side);
        }
        return quantum;
      };
      auto minRecess = [&] { return std::max(p.door_min_recess_m, quantumHere() * cos_gap); };
      // An ajar leaf's free end stands clearly behind the wall: beyond the noise band.
      auto minLeafDepthFor = [&](double q) {
        return p.door_min_recess_m + p.door_noise_sigmas * std::sqrt(sigma * sigma + q * q / 12.0) * cos_gap;
      };
      auto minLeafDepth = [&] { return minLeafDepthFor(quantumHere()); };
      // The quantum is one of a few steps, 0 to kMaxRangeQuantum, and the thresholds grow
      // with it (each operation is monotonic in it, rounding included, the factors being
      // non-negative): a depth beyond the largest step's threshold passes, and an ajar leaf's
      // depth short of no step's fails, whatever the ranges' grid; the histogram is read
      // only in between (most recessed leaves stand well behind 10 cm cos(incidence)).
      const bool monotonic = cos_gap >= 0.0;  // false for a NaN
      const double recess_any_quantum = kMaxRangeQuantum * cos_gap;
      const double leaf_depth_any_quantum = minLeafDepthFor(kMaxRangeQuantum);
      const double leaf_depth_no_quantum = minLeafDepthFor(0.0);
      auto behindMinRecess = [&](double offset) {  // offset >= minRecess(), offset >= door_min_recess_m known
        return (monotonic && offset >= recess_any_quantum) || offset >= minRecess();
      };
      auto behindMinLeafDepth = [&](double depth) {  // depth >= minLeafDepth()
        if (monotonic && depth >= leaf_depth_any_quantum) return true;
        if (monotonic && !(depth >= leaf_depth_no_quantum)) return false;
        return depth >= minLeafDepth();
      };
      double closed_support = 0.0, ajar_support = 0.0;
      Eigen::Vector2d hinge_point = Eigen::Vector2d::Zero();
      // A segment end at the hinge: along the wall near a jamb, at most a frame's depth behind.
      auto hingeDistance = [&](const Eigen::Vector2d& q) {
        const double depth = a.signedDistance(q);
        if (depth < -p.door_hinge_tolerance_m || depth > p.door_max_recess_m + p.door_hinge_tolerance_m) {
          return std::numeric_limits<double>::infinity();
        }
        const double s = q.dot(t);
        return std::min(std::abs(s - s_jamb_a), std::abs(s - s_jamb_b));
      };
      for (std::size_t m = (i + 1) % n; m != j; m = (m + 1) % n) {
        const Segment& s = segs[m];
        const double sin_angle = std::abs(cross(s.direction(), t));
        // A reveal runs across the wall; a segment along it near a jamb is a leaf.
        const int reveal_of_start = revealOf(s.start);
        if (sin_angle > sin_leaf_parallel_ && reveal_of_start != 0 && reveal_of_start == revealOf(s.end)) continue;
        const double offset = a.signedDistance(s.centroid);
        if (sin_angle <= sin_leaf_parallel_) {
          if (offset >= p.door_min_recess_m && offset <= p.door_max_recess_m && behindMinRecess(offset)) {
            closed_support += static_cast<double>(s.num_points) / total;
          }
        } else if (offset > 0.0 && s.length_m >= p.door_min_ajar_leaf_m) {
          const double hinge = std::min(hingeDistance(s.start), hingeDistance(s.end));
          if (hinge <= p.door_hinge_tolerance_m && s.length_m / width > ajar_support &&
              behindMinLeafDepth(std::max(a.signedDistance(s.start), a.signedDistance(s.end)))) {
            ajar_support = std::min(1.0, s.length_m / width);
            // The leaf's end on the wall line is the hinge, hence a jamb.
            hinge_point = std::abs(a.signedDistance(s.start)) < std::abs(a.signedDistance(s.end)) ? s.start : s.end;
          }
        }
      }
      // A lost return on a wall at a grazing angle looks like a beam through an opening:
      // lost returns count as beyond only as many as the beams seen beyond.
      const std::size_t lost = beyond - seen_beyond;
      const double beyond_fraction = static_cast<double>(seen_beyond + std::min(lost, seen_beyond)) / total;
      FeatureType type;
      double support;
      if (closed_support >= p.door_min_leaf_fraction) {
        type = FeatureType::kDoorClosed;
        support = std::min(1.0, closed_support);
      } else if (ajar_support > 0.0) {
        type = FeatureType::kDoorAjar;
        support = ajar_support;
      } else if (beyond_fraction >= p.door_min_beyond_fraction) {
        type = FeatureType::kDoorOpen;
        support = beyond_fraction;
      } else {
        break;  // something else fills the gap
      }

      if (type == FeatureType::kDoorAjar) {
        Jamb& hinge_jamb = (hinge_point - jamb_a.point).norm() < (hinge_point - jamb_b.point).norm() ? jamb_a : jamb_b;
        hinge_jamb.point = hinge_point - a.signedDistance(hinge_point) * a.normal;
      }
      Feature f;
      f.type = type;
      f.jamb_a = jamb_a.point;
      f.jamb_b = jamb_b.point;
      f.position = 0.5 * (jamb_a.point + jamb_b.point);
      f.theta_rad = a.theta_rad;
      f.width_m = (jamb_b.point - jamb_a.point).norm();
      const double wall_factor = std::min(1.0, std::min(a.length_m, b.length_m) / (2.0 * p.door_min_wall_m));
      const double beam_factor = std::min(1.0, total / (2.0 * static_cast<double>(p.door_min_gap_beams)));
      f.confidence = std::clamp(support * wall_factor * beam_factor, 0.0, 1.0);
      // Covariance: the centre is rho n + s t on the wall's line, s (its coordinate along
      // the line) the mean of the two jambs' coordinates.
      const double var_a = jamb_a.variance_m2, var_b = jamb_b.variance_m2;
      const Eigen::Vector2d tn = tangentOf(a);
      f.covariance = doorCovariance(a.normal, a.rho_m, tn, f.position.dot(tn), a.covariance, var_a, var_b);
      f.width_variance_m2 = var_a + var_b;
      f.segment_a = static_cast<std::uint32_t>(i);
      f.segment_b = static_cast<std::uint32_t>(j);
      out.push_back(f);
      break;
    }
  }
}

// The flush-leaf pass is compiled twice on x86-64 Linux with GCC, for AVX2 and for the
// baseline, and the loader picks one per CPU: its vectorised loops over every point of a
// long wall (the per-beam terms with their division, the steps) take four doubles per
// instruction instead of two. AVX2 brings no FMA (a separate target feature; GCC fuses a
// multiply and an add only where FMA exists), each lane is the same correctly rounded
// operation as the scalar one and no sum is reassociated (the prefix sums stay scalar, in
// scan order): both copies give the same bits (decision 91). Not under ThreadSanitizer: the
// loader runs the copy's selector before TSan's runtime is up, and the instrumented selector
// crashes the program at start.
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && defined(__linux__) && \
    !defined(__SANITIZE_THREAD__)
#define LIDARSEG_FLUSH_LEAF_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define LIDARSEG_FLUSH_LEAF_CLONES
#endif
// Its per-beam loops are lambdas called from two places (a run that wraps past the last beam
// has two ranges); inlined, so that they are compiled in each copy (an out-of-line lambda
// is neither cloned nor given the locals' registers).
#if defined(__GNUC__)
#define LIDARSEG_INLINE __attribute__((always_inline))
#else
#define LIDARSEG_INLINE
#endif

LIDARSEG_FLUSH_LEAF_CLONES
void FeatureDetector::detectShallowDoors(const Segmentation& segmentation, const ScanGeometry& geometry,
                                         std::vector<Feature>& out) const {
  const FeatureDetectorParams& p = params_;
  if (p.door_shallow_min_sigmas <= 0.0) return;
  const std::vector<Segment>& segs = segmentation.level(p.level).segments;
  const std::size_t num_beams = segmentation.points.size();
  const std::size_t W = p.door_shallow_window;
  // A leaf of a run: its points [k, e), `depth` behind the mean `wall` of the run's wall
  // points, `t` standard errors of the difference.
  struct Leaf {
    std::size_t k = 0, e = 0;
    double t = 0.0, depth = 0.0, wall = 0.0;
  };
  // Per-thread scratch: no allocation once grown.
  thread_local std::vector<double> tl_weight, tl_sum, tl_sum_sq, tl_plain, tl_along, tl_steps;
  thread_local std::vector<double> tl_before_mean, tl_before_ss, tl_after_mean, tl_after_ss;
  thread_local std::vector<double> tl_before_plain, tl_after_plain;
  thread_local std::vector<double> tl_term_r, tl_term_w, tl_term_along;
  thread_local std::vector<std::uint32_t> tl_beam_of, tl_starts, tl_ends, tl_wall_from, tl_wall_to, tl_bin_at;
  thread_local std::vector<Leaf> tl_leaves, tl_candidates;
  // Bound once: every use of a thread_local may look its address up again.
  std::vector<double>&weight = tl_weight, &sum = tl_sum, &sum_sq = tl_sum_sq, &steps = tl_steps;
  std::vector<double>&plain = tl_plain, &along_of = tl_along;
  std::vector<double>&term_r_v = tl_term_r, &term_w_v = tl_term_w, &term_along_v = tl_term_along;
  std::vector<double>&before_mean = tl_before_mean, &before_ss = tl_before_ss, &after_mean = tl_after_mean,
                      &after_ss = tl_after_ss;
  std::vector<double>&before_plain = tl_before_plain, &after_plain = tl_after_plain;
  std::vector<std::uint32_t>&beam_of = tl_beam_of, &starts = tl_starts, &ends = tl_ends;
  std::vector<std::uint32_t>&wall_from = tl_wall_from, &wall_to = tl_wall_to, &bin_at = tl_bin_at;
  std::vector<Leaf>&leaves = tl_leaves, &candidates = tl_candidates;
  // A run of consecutive segments on one line (parallel, each end within the collinearity
  // tolerance of the first's line, no beam between them): the segmenter may
  // have split a shallow leaf from one wall only.
  std::size_t next = 0;
  for (std::size_t si = 0; si < segs.size(); si = next) {
    const Segment& s = segs[si];
    std::size_t last = si;
    while (last + 1 < segs.size() && segs[last + 1].first_beam == segs[last].last_beam + 1 &&
           s.normal.dot(segs[last + 1].normal) >= cos_collinear_ &&
           onLineOf(p, geometry.range_sigma_m, s, segs[last + 1].start) &&
           onLineOf(p, geometry.range_sigma_m, s, segs[last + 1].end)) {
      ++last;
    }
    next = last + 1;
    const double run_length = (segs[last].end - s.start).norm();
    if (run_length < 2.0 * p.door_min_wall_m + p.door_min_width_m) continue;
    const Eigen::Vector2d t = s.direction();
    const std::size_t span = (segs[last].last_beam + num_beams - s.first_beam) % num_beams + 1;
    if (sum.size() < span + 1) {
      weight.resize(span + 1);
      plain.resize(span + 1);
      along_of.resize(span + 1);
      sum.resize(span + 1);
      sum_sq.resize(span + 1);
      beam_of.resize(span);
      steps.resize(span);
      term_r_v.resize(span);
      term_w_v.resize(span);
      term_along_v.resize(span);
    }
    // The wall's line: fitted (total least squares) to every point of the run. The first
    // segment's line would do for one segment, but a short first piece's direction is
    // unsure (sigma / (L sqrt(n / 12)): 20 mrad for 0.5 m and 20 points), and across a run
    // several metres long that tilt is a ramp of centimetres, which a comparison of means
    // reads as a leaf.
    // (The segments' moments add: the run's fit costs one sum per segment.)
    LineMoments mom;
    for (std::size_t m = si; m <= last; ++m) mom += segs[m].moments;
    if (mom.count < 2.0) continue;
    const double mx = mom.sum_x / mom.count, my = mom.sum_y / mom.count;
    const double cxx = mom.sum_xx / mom.count - mx * mx, cxy = mom.sum_xy / mom.count - mx * my,
                 cyy = mom.sum_yy / mom.count - my * my;
    const double phi = 0.5 * std::atan2(2.0 * cxy, cxx - cyy);  // the direction of most spread
    Eigen::Vector2d normal(-std::sin(phi), std::cos(phi));
    if (normal.dot(s.normal) < 0.0) normal = -normal;
    const double rho_line = normal.x() * mx + normal.y() * my;
    // Prefix sums of the points' distances behind that line (and of their squares), in scan
    // order, each weighted by 1 / cos^2 of its incidence: a range error moves a point along
    // its beam, so across the wall by cos(incidence) of it (the segments' noise model). The
    // weighted scatter then measures the range noise itself, the same along the whole wall,
    // and a mean's variance is sigma^2 / (sum of the weights): a stretch seen head-on is not
    // judged by the scatter of the wall's oblique end.
    std::size_t n = 0;
    weight[0] = sum[0] = sum_sq[0] = plain[0] = 0.0;
    const double nx = normal.x(), ny = normal.y(), rho = rho_line;
    double acc_plain = 0.0;  // in a register: no store-to-load chain through the array
    // The run's beams are one or (wrapping past the last beam) two contiguous ranges: no
    // wrap test per point; raw pointers, as the stores cannot move the vectors. Each range
    // in two passes: every beam's terms first (no branch, no dependency between beams),
    // then the prefix sums over the valid beams, in scan order.
    const Eigen::Vector2d* const points = segmentation.points.data();
    double *const weight_p = weight.data(), *const sum_p = sum.data(), *const sum_sq_p = sum_sq.data(),
                  *const plain_p = plain.data(), *const along_p = along_of.data();
    double *const term_r = term_r_v.data(), *const term_w = term_w_v.data(), *const term_along = term_along_v.data();
    std::uint32_t* const beam_p = beam_of.data();
    const double tx = t.x(), ty = t.y();
    // First only what places the candidate steps and the walls beside them: the plain
    // distances' prefix sums and the abscissae. The weighted sums (a division per point and
    // three more dependent sums) are computed by weighRun only for a run with a pair of
    // steps whose plain means are behind the wall on both sides by `edge` (below).
    auto accumulate = [&](std::size_t from, std::size_t to) LIDARSEG_INLINE {
      const Eigen::Vector2d* const q = points + from;
      const std::size_t count = to - from;
#pragma omp simd
      for (std::size_t c = 0; c < count; ++c) {
        const double x = q[c].x(), y = q[c].y();
        term_r[c] = (nx * x + ny * y) - rho;
        term_along[c] = x * tx + y * ty;
      }
      // (The sum and the count in locals: no store-to-load chain through the captures.)
      double sum_here = acc_plain;
      std::size_t n_here = n;
      for (std::size_t c = 0; c < count; ++c) {
        if (!std::isfinite(q[c].x())) continue;
        sum_here += term_r[c];
        along_p[n_here] = term_along[c];
        beam_p[n_here] = static_cast<std::uint32_t>(from + c);
        ++n_here;
        plain_p[n_here] = sum_here;
      }
      acc_plain = sum_here;
      n = n_here;
    };
    // The weighted prefix sums over the same valid beams in the same order (the same
    // expressions as before this split, so the same values).
    std::size_t n_weighed = 0;
    double acc_w = 0.0, acc = 0.0, acc_sq = 0.0;
    auto accumulateWeighted = [&](std::size_t from, std::size_t to) LIDARSEG_INLINE {
      const Eigen::Vector2d* const q = points + from;
      const std::size_t count = to - from;
#pragma omp simd
      for (std::size_t c = 0; c < count; ++c) {
        const double x = q[c].x(), y = q[c].y();
        const double nq = nx * x + ny * y;
        const double sq = x * x + y * y;
        term_r[c] = nq - rho;
        term_w[c] = sq / std::max(nq * nq, 1e-12 * sq);
      }
      double sw = acc_w, swr = acc, swrr = acc_sq;
      std::size_t i = n_weighed;
      for (std::size_t c = 0; c < count; ++c) {
        if (!std::isfinite(q[c].x())) continue;
        const double r = term_r[c], w = term_w[c];
        sw += w;
        swr += w * r;
        swrr += w * r * r;
        ++i;
        weight_p[i] = sw;
        sum_p[i] = swr;
        sum_sq_p[i] = swrr;
      }
      acc_w = sw;
      acc = swr;
      acc_sq = swrr;
      n_weighed = i;
    };
    const std::size_t first_beam = s.first_beam;
    const bool wraps = first_beam + span > num_beams;
    if (!wraps) {
      accumulate(first_beam, first_beam + span);
    } else {
      accumulate(first_beam, num_beams);
      accumulate(0, first_beam + span - num_beams);
    }
    if (n < 2 * p.door_min_wall_points + 2 * W) continue;
    auto along = [&](std::size_t k) { return along_of[k]; };
    auto mean = [&](std::size_t a, std::size_t b) { return (sum[b] - sum[a]) / (weight[b] - weight[a]); };
    auto plainMean = [&](std::size_t a, std::size_t b) { return (plain[b] - plain[a]) / static_cast<double>(b - a); };
    auto scatter = [&](std::size_t a, std::size_t b) {  // weighted squared deviations from the mean
      return std::max(0.0, (sum_sq[b] - sum_sq[a]) - (sum[b] - sum[a]) * (sum[b] - sum[a]) / (weight[b] - weight[a]));
    };
    const double edge = 0.5 * p.door_shallow_min_recess_m;
    if (starts.size() < n + 1) {
      starts.resize(n + 1);
      ends.resize(n + 1);
      wall_from.resize(n + 1);
      wall_to.resize(n + 1);
      before_mean.resize(n + 1);
      before_ss.resize(n + 1);
      after_mean.resize(n + 1);
      after_ss.resize(n + 1);
      before_plain.resize(n + 1);
      after_plain.resize(n + 1);
      bin_at.resize(n + 1);
    }
    // The candidate steps are looked for on bins of consecutive points, each at most
    // door_min_wall_m / W long along the wall (issue 18's speed rule): W bins then span at
    // most the door_min_wall_m of wall every door rule asks beside a leaf, as W points do
    // where the beams are that sparse; where they are sparser a bin is one point, as
    // before. Near the sensor, where the beams are dense, a bin holds several points: the
    // step windows average more of them (less noise, fewer candidate steps, each placed to
    // within its bin and then refined to a point, below) and the search over the steps, the
    // walks and the pairs go over bins instead of points. The bins are the cells of a grid
    // of that step along the wall: a bin ends where a point's cell differs from the one
    // before's (branch-free).
    const double inv_bin = static_cast<double>(W) / p.door_min_wall_m;
    std::size_t nb = 1;
    bin_at[0] = 0;
    {
      double cell = std::floor(along_p[0] * inv_bin);
      for (std::size_t i = 1; i < n; ++i) {
        const double c = std::floor(along_p[i] * inv_bin);
        bin_at[nb] = static_cast<std::uint32_t>(i);
        nb += c != cell;
        cell = c;
      }
    }
    bin_at[nb] = static_cast<std::uint32_t>(n);
    if (nb < 2 * W + 4) continue;
    // Step at bin boundary j: the mean of the points of the W bins from j on minus that of
    // the W bins before. Leaf starts are its local maxima above `edge`, leaf ends its local
    // minima below -edge. (Plain means: the steps only place the candidates; the test below
    // weighs the points.)
    auto binStep = [&](std::size_t lo, std::size_t mid, std::size_t hi) {  // point indices
      return (plain[hi] - plain[mid]) / static_cast<double>(hi - mid) -
             (plain[mid] - plain[lo]) / static_cast<double>(mid - lo);
    };
    // (The mean of the W bins from j on is also the mean before j + W: one division per bin.
    // The same expressions as binStep, so the same values.)
    double* const window_mean = term_along;  // free once the abscissae are stored
    for (std::size_t j = 0; j + W <= nb; ++j) {
      window_mean[j] = (plain[bin_at[j + W]] - plain[bin_at[j]]) / static_cast<double>(bin_at[j + W] - bin_at[j]);
    }
    for (std::size_t j = W; j + W <= nb; ++j) steps[j] = window_mean[j] - window_mean[j - W];
    // (Below, "points" and "steps" are the bins and their boundaries' steps.)
    // A step is located to within the window: of two candidates closer than W points, only
    // the larger is a step (the largest within W points on either side; ties to the first).
    // Two starts are therefore more than W points apart, and a start is the first largest
    // step of any W + 1 consecutive steps holding it (they all lie within its window). So
    // the steps are cut into blocks of W + 1, and only each block's first largest (first
    // smallest, for an end) is put to the window's test: the same list of starts and ends,
    // in the same order, as testing every step against its neighbours first and then the
    // window (decision 82). Branch-free, and the whole window compared (a fixed number of
    // comparisons): testing only the steps outside the block, or branching on whether the
    // block's largest step reaches `edge`, took fewer instructions and more time (their loop
    // lengths and branches follow the noise); the extremes that reach `edge` are collected
    // without a branch and tested in a loop of their own (decision 91). The comparisons
    // assume finite steps, as the plain sums are here; with a non-finite sum the run is
    // searched as before.
    std::size_t num_starts = 0, num_ends = 0;
    double* const step_p = steps.data();
    std::uint32_t *const start_p = starts.data(), *const end_p = ends.data();
    // (The window split at k: no test of j against k per point, and an end's test compares
    // the steps themselves, not their negatives: negation is exact, so the same outcome.)
    // (Every step of the window compared, without an early exit: the windows have the same
    // length but for the ends of the run, so the loops are predictable; the tests are pure,
    // so the outcome is the same.)
    auto largestWithin = [&](std::size_t k) {
      const double sk = step_p[k];
      const std::size_t lo = k >= 2 * W ? k - W : W, hi = std::min(k + W, nb - W);
      bool largest = true;
      for (std::size_t j = lo; j < k; ++j) largest &= step_p[j] < sk;
      for (std::size_t j = k + 1; j <= hi; ++j) largest &= step_p[j] <= sk;
      return largest;
    };
    auto smallestWithin = [&](std::size_t k) {
      const double sk = step_p[k];
      const std::size_t lo = k >= 2 * W ? k - W : W, hi = std::min(k + W, nb - W);
      bool smallest = true;
      for (std::size_t j = lo; j < k; ++j) smallest &= step_p[j] > sk;
      for (std::size_t j = k + 1; j <= hi; ++j) smallest &= step_p[j] >= sk;
      return smallest;
    };
    if (std::isfinite(acc_plain)) {
      const std::size_t k_end = nb - W;  // the last step
      for (std::size_t b0 = W; b0 <= k_end; b0 += W + 1) {
        const std::size_t b1 = std::min(b0 + W, k_end);
        std::size_t i_max = b0, i_min = b0;
        double v_max = step_p[b0], v_min = step_p[b0];
        for (std::size_t j = b0 + 1; j <= b1; ++j) {
          const double v = step_p[j];
          const bool larger = v > v_max, smaller = v < v_min;
          v_max = larger ? v : v_max;
          i_max = larger ? j : i_max;
          v_min = smaller ? v : v_min;
          i_min = smaller ? j : i_min;
        }
        start_p[num_starts] = static_cast<std::uint32_t>(i_max);
        num_starts += v_max >= edge;
        end_p[num_ends] = static_cast<std::uint32_t>(i_min);
        num_ends += v_min <= -edge;
      }
    } else {
      // First the neighbours' test, branch-free (the noise makes it unpredictable), then the
      // window's for the few left.
      // The first and last steps have one neighbour only: tested apart, so that the loop over
      // the others needs no test of k. (nb >= 2 W + 4 here, so they are distinct.)
      auto keepStep = [&](std::size_t k, bool is_start, bool is_end) {
        start_p[num_starts] = static_cast<std::uint32_t>(k);
        num_starts += is_start;
        end_p[num_ends] = static_cast<std::uint32_t>(k);
        num_ends += is_end;
      };
      keepStep(W, step_p[W] >= edge && step_p[W + 1] <= step_p[W], step_p[W] <= -edge && step_p[W + 1] >= step_p[W]);
      for (std::size_t k = W + 1; k + W < nb; ++k) {
        const double sk = step_p[k], before = step_p[k - 1], after = step_p[k + 1];
        keepStep(k, (sk >= edge) & (before < sk) & (after <= sk), (sk <= -edge) & (before > sk) & (after >= sk));
      }
      const std::size_t k_last = nb - W;
      keepStep(k_last, step_p[k_last] >= edge && step_p[k_last - 1] < step_p[k_last],
               step_p[k_last] <= -edge && step_p[k_last - 1] > step_p[k_last]);
    }
    // Then the window's test, only for the candidates kept so far (the block extremes that
    // reach `edge`, about half of them on a noisy wall; or the steps that pass their
    // neighbours' test), in a loop of its own: a start must pass both tests, and the tests
    // are pure, so the list and its order are those of testing both in one loop, without
    // spending the window's comparisons on the others or branching on the noise
    // (decision 91).
    {
      std::size_t kept = 0;
      for (std::size_t i = 0; i < num_starts; ++i) {
        const std::uint32_t k = start_p[i];
        start_p[kept] = k;
        kept += largestWithin(k);
      }
      num_starts = kept;
      kept = 0;
      for (std::size_t i = 0; i < num_ends; ++i) {
        const std::uint32_t k = end_p[i];
        end_p[kept] = k;
        kept += smallestWithin(k);
      }
      num_ends = kept;
    }
    // Each step placed to a point: the point between the bins on either side of its bin
    // boundary where the same two windows (their outer ends kept) differ most (ties to the
    // boundary, then to the first). Where the bins are single points that is the boundary.
    auto refine = [&](std::uint32_t* list, std::size_t count, bool largest) {
      for (std::size_t i = 0; i < count; ++i) {
        const std::size_t j = list[i];
        const std::size_t lo = bin_at[j - W], hi = bin_at[j + W];
        std::size_t best = bin_at[j];
        if (bin_at[j + 1] - bin_at[j - 1] > 2) {
          double best_step = binStep(lo, best, hi);
          for (std::size_t k = bin_at[j - 1] + 1; k < bin_at[j + 1]; ++k) {
            const double v = binStep(lo, k, hi);
            if (largest ? v > best_step : v < best_step) {
              best_step = v;
              best = k;
            }
          }
        }
        list[i] = static_cast<std::uint32_t>(best);
      }
    };
    refine(start_p, num_starts, true);
    refine(end_p, num_ends, false);
    // No leaf without both a start and an end: nothing below would be found.
    if (num_starts == 0 || num_ends == 0) continue;
    // A wall may hold several doors: the candidates that pass are taken most significant
    // first, each clear of those taken before (with a wall of door_min_wall_m and
    // door_min_wall_points between).
    candidates.clear();
    leaves.clear();
    auto clearOfLeaves = [&](std::size_t k, std::size_t e) {
      for (const Leaf& l : leaves) {
        const bool before = e + p.door_min_wall_points <= l.k && along(l.k) - along(e) >= p.door_min_wall_m;
        const bool after = l.e + p.door_min_wall_points <= k && along(k) - along(l.e) >= p.door_min_wall_m;
        if (!before && !after) return false;
      }
      return true;
    };
    // The wall beside a leaf is the door_min_wall_m of it on each side, not the whole run: a
    // wall bent by a few centimetres over metres (a rough wall; a scan taken while turning,
    // rolling shutter) puts a stretch of its middle behind the run's mean, but hardly
    // behind the wall right beside it; a door's leaf steps back at its jambs. wall_from[i]:
    // the first point within door_min_wall_m before the i-th start; wall_to[m]: one past the
    // last point within door_min_wall_m after the m-th end's last leaf point (two pointers
    // over the few steps, not over every point; wall_from only for the starts that pair,
    // below). The plain mean of the wall after each end is taken with its walk (for the
    // pairs' first test, below); the weighted mean and scatter, which need the run's
    // weighted sums, only for the ends of the pairs that pass it (weighRun, readyEnd).
    for (std::size_t m = 0, b = 0; m < num_ends; ++m) {
      const std::size_t e = ends[m];
      b = std::max(b, e);
      while (b < n && along(b) <= along(e - 1) + p.door_min_wall_m) ++b;
      wall_to[m] = static_cast<std::uint32_t>(b);
      after_plain[m] = plainMean(e, b);  // (not used where b - e < door_min_sparse_wall_points)
      after_ss[m] = -1.0;                // not yet computed
    }
    bool weighed = false;
    auto weighRun = [&] {
      if (!wraps) {
        accumulateWeighted(first_beam, first_beam + span);
      } else {
        accumulateWeighted(first_beam, num_beams);
        accumulateWeighted(0, first_beam + span - num_beams);
      }
      weighed = true;
    };
    // The end's weighted mean and scatter: once per end (they depend on it only).
    auto readyEnd = [&](std::size_t m) {
      const std::size_t e = ends[m], b = wall_to[m];
      after_mean[m] = mean(e, b);
      after_ss[m] = scatter(e, b);
    };
    // The leaf [k, e) against the wall beside it: its depth and t statistic, the leaf's mean
    // judged with the pooled scatter of the three pieces (each about its own mean) or with
    // its own, when that is larger (a far or rough stretch is noisier than the rest).
    auto evaluate = [&](std::size_t ks, std::size_t m, Leaf& leaf) {
      const std::size_t k = starts[ks], e = ends[m];
      const std::size_t a = wall_from[ks], b = wall_to[m];
      if (k - a < p.door_min_sparse_wall_points || b - e < p.door_min_sparse_wall_points) return false;
      const double in_sum = sum[e] - sum[k];
      const double w_in = weight[e] - weight[k];
      const double level = in_sum / w_in;
      // Behind the wall on both sides: a stretch from one jamb to somewhere inside a wide
      // leaf has the leaf itself on its far side.
      if (level - before_mean[ks] < p.door_shallow_min_recess_m || level - after_mean[m] < p.door_shallow_min_recess_m) {
        return false;
      }
      const double wall_sum = (sum[k] - sum[a]) + (sum[b] - sum[e]);
      const double w_wall = (weight[k] - weight[a]) + (weight[b] - weight[e]);
      const double wall = wall_sum / w_wall;
      const double depth = level - wall;
      if (depth < p.door_shallow_min_recess_m || depth > p.door_shallow_max_recess_m) return false;
      const double ss_in = scatter(k, e);
      const double var = (ss_in + before_ss[ks] + after_ss[m]) / std::max(1.0, static_cast<double>(b - a) - 3.0);
      const double var_in = std::max(var, ss_in / std::max(1.0, static_cast<double>(e - k) - 1.0));
      leaf = {k, e, depth / std::sqrt(std::max(var_in / w_in + var / w_wall, 1e-24)), depth, wall};
      return true;
    };
    // The wall before a start (its walk, mean and scatter) only for the starts with a pair
    // that passes the first test, when first needed. The walks chain: each goes on from
    // where the one of the start before it stopped. The walks of the starts skipped since
    // the last one walked may be left out when none of their abscissae exceeds this
    // start's: every point they would pass is then before this walk's limit too (the limit
    // is the abscissa less door_min_wall_m, as monotonic as the abscissa), so this walk
    // stops at the same point. Otherwise they are walked first, in order (decision 92).
    std::size_t walk_a = 0, walked = 0;
    auto walkTo = [&](std::size_t k) {
      while (walk_a < k && along(walk_a) < along(k) - p.door_min_wall_m) ++walk_a;
    };
    auto readyStart = [&](std::size_t ks) {
      const double here = along(starts[ks]);
      bool in_order = true;
      for (std::size_t j = walked; j < ks; ++j) in_order &= along(starts[j]) <= here;
      if (!in_order) {
        for (std::size_t j = walked; j < ks; ++j) walkTo(starts[j]);
      }
      const std::size_t k = starts[ks];
      walkTo(k);
      wall_from[ks] = static_cast<std::uint32_t>(walk_a);
      walked = ks + 1;
      if (k - walk_a < p.door_min_sparse_wall_points) return;  // never evaluated
      before_plain[ks] = plainMean(walk_a, k);
      before_ss[ks] = -1.0;  // the weighted mean and scatter: when a pair first passes the first test
    };
    // The first test of a pair, before any weighted sum (issue 18's speed rule): the leaf's
    // plain mean at least `edge` = door_shallow_min_recess_m / 2 behind the plain means of
    // the walls on both sides, as the steps that placed k and e are plain means held to
    // `edge`. The full test below asks the weighted means to be door_shallow_min_recess_m
    // behind; a weighted mean departs from the plain mean of the same points by a small
    // fraction of their scatter (the weights 1 / cos^2 of the incidence change little
    // across 0.25 m of wall or a door's width), far less than the `edge` of slack. Most
    // pairs of noise steps fail it, and a run whose pairs all fail is never weighed: the
    // division per point and the three dependent weighted sums are skipped.
    std::size_t first_end = 0;
    for (std::size_t ks = 0; ks < num_starts; ++ks) {
      const std::size_t k = starts[ks];
      if (k < p.door_min_wall_points || along(k) - along(0) < p.door_min_wall_m) continue;
      while (first_end < num_ends && ends[first_end] <= k) ++first_end;
      bool ready = false;
      for (std::size_t m = first_end; m < num_ends; ++m) {
        const std::size_t e = ends[m];
        const double width = along(e) - along(k);
        if (width > p.door_max_width_m) break;
        if (width < p.door_min_width_m || e - k < p.door_min_gap_beams) continue;
        if (n - e < p.door_min_wall_points || along(n - 1) - along(e) < p.door_min_wall_m) continue;
        if (!ready) {
          readyStart(ks);
          ready = true;
        }
        if (k - wall_from[ks] < p.door_min_sparse_wall_points || wall_to[m] - e < p.door_min_sparse_wall_points) continue;
        const double plain_level = plainMean(k, e);
        if (plain_level - before_plain[ks] < edge || plain_level - after_plain[m] < edge) continue;
        if (!weighed) weighRun();
        if (before_ss[ks] < 0.0) {
          before_mean[ks] = mean(wall_from[ks], k);
          before_ss[ks] = scatter(wall_from[ks], k);
        }
        if (after_ss[m] < 0.0) readyEnd(m);
        Leaf c;
        if (evaluate(ks, m, c) && c.t >= p.door_shallow_min_sigmas) candidates.push_back(c);
      }
    }
    std::sort(candidates.begin(), candidates.end(), [](const Leaf& a, const Leaf& b) { return a.t > b.t; });
    for (const Leaf& c : candidates) {
      if (clearOfLeaves(c.k, c.e)) leaves.push_back(c);
    }
    for (const Leaf& leaf : leaves) {
      // One opening holds one door: a leaf deep enough to be its own segment was found
      // between its walls already, and a wall cut into two runs may show the same leaf
      // twice. A leaf overlapping a door found before on the same wall (along it, and within
      // a recess of its line) is that door.
      const Eigen::Vector2d& first = segmentation.points[beam_of[leaf.k]];
      const Eigen::Vector2d& end_point = segmentation.points[beam_of[leaf.e - 1]];
      const double s0 = std::min(first.dot(t), end_point.dot(t)), s1 = std::max(first.dot(t), end_point.dot(t));
      const double tol = p.door_reveal_tolerance_m;
      bool known = false;
      for (std::size_t d = 0; d < out.size() && !known; ++d) {
        if (!isDoor(out[d].type)) continue;
        const double a0 = out[d].jamb_a.dot(t), b0 = out[d].jamb_b.dot(t);
        known = std::abs(normal.dot(out[d].position) - rho_line) <= p.door_max_recess_m + tol &&
                s0 < std::max(a0, b0) + tol && std::min(a0, b0) - tol < s1;
      }
      if (known) continue;
      // Seen too obliquely, a step is smeared over few, far-apart points: its jambs are unsure.
      const Eigen::Vector2d centre =
          0.5 * (segmentation.points[beam_of[leaf.k]] + segmentation.points[beam_of[leaf.e - 1]]);
      const double cos_incidence = std::abs(normal.dot(centre.normalized()));
      if (cos_incidence < cos_shallow_incidence_) continue;
      // Ranges on a grid of step q leave steps up to q cos(incidence) on a plain wall (a run
      // of beams reading the same range), correlated over many points: the t-test cannot see
      // through them, so the leaf must be deeper than that.
      const std::size_t from = beam_of[leaf.k > W ? leaf.k - W : 0];
      const std::size_t to = beam_of[std::min(n - 1, leaf.e + W)];
      const double quantum = rangeQuantum(segmentation, from, (to + num_beams - from) % num_beams + 1);
      if (leaf.depth < quantum * cos_incidence) continue;
      // The wall's line is the run's moved to the wall beside the leaf; the jambs lie on it
      // between the last wall point and the first leaf point of each step.
      const double rho_wall = rho_line + leaf.wall;
      auto onWall = [&](const Eigen::Vector2d& q) -> Eigen::Vector2d {
        return q - (normal.dot(q) - rho_wall) * normal;
      };
      const Eigen::Vector2d& q0 = segmentation.points[beam_of[leaf.k - 1]];
      const Eigen::Vector2d& q1 = segmentation.points[beam_of[leaf.k]];
      const Eigen::Vector2d& q2 = segmentation.points[beam_of[leaf.e - 1]];
      const Eigen::Vector2d& q3 = segmentation.points[beam_of[leaf.e]];
      Feature f;
      f.type = FeatureType::kDoorClosed;
      f.jamb_a = onWall(0.5 * (q0 + q1));
      f.jamb_b = onWall(0.5 * (q2 + q3));
      f.position = 0.5 * (f.jamb_a + f.jamb_b);
      f.theta_rad = std::atan2(normal.y(), normal.x());  // only for a door found: most runs hold none
      f.width_m = (f.jamb_b - f.jamb_a).norm();
      f.confidence = std::clamp(leaf.t / (2.0 * p.door_shallow_min_sigmas), 0.0, 1.0) *
                     std::min(1.0, leaf.depth / (2.0 * p.door_min_recess_m));
      // Covariance as for a door between two walls: each jamb uniform over its step's spacing.
      const double var_a = (q1 - q0).squaredNorm() / 12.0 + s.covariance(0, 0);
      const double var_b = (q3 - q2).squaredNorm() / 12.0 + s.covariance(0, 0);
      const Eigen::Vector2d tn(-normal.y(), normal.x());
      f.covariance = doorCovariance(normal, rho_wall, tn, f.position.dot(tn), s.covariance, var_a, var_b);
      f.width_variance_m2 = var_a + var_b;
      f.segment_a = static_cast<std::uint32_t>(si);
      f.segment_b = static_cast<std::uint32_t>(last);
      out.push_back(f);
    }
  }
}

void FeatureDetector::detectCorners(const Segmentation& segmentation, std::vector<Feature>& out) const {
  const FeatureDetectorParams& p = params_;
  const std::vector<Segment>& segs = segmentation.level(params_.level).segments;
  const std::size_t n = segs.size();
  if (n < 2) return;
  const std::size_t num_doors = out.size();
  const std::size_t pairs = segmentation.wraps_around ? n : n - 1;
  auto armOk = [&](const Segment& s) {
    return s.length_m >= p.corner_min_arm_m && s.num_points >= p.corner_min_points;
  };
  // Tries the corner between segments i and j; `slack` (m) is the length of a short piece
  // of the corner itself between them (0 for neighbours).
  auto tryCorner = [&](std::size_t i, std::size_t j, double slack) {
    const Segment& a = segs[i];
    const Segment& b = segs[j];
    if (!armOk(a) || !armOk(b)) return false;
    const double gap_limit = p.corner_max_gap_m + slack;
    if ((b.start - a.end).norm() > gap_limit) return false;
    const double det = cross(a.normal, b.normal);
    if (std::abs(det) < 1e-9) return false;
    // Intersection of the two lines: n_a . c = rho_a, n_b . c = rho_b.
    Eigen::Matrix2d M;
    M << a.normal.x(), a.normal.y(), b.normal.x(), b.normal.y();
    const Eigen::Matrix2d Minv = M.inverse();
    const Eigen::Vector2d c = Minv * Eigen::Vector2d(a.rho_m, b.rho_m);
    if ((c - a.end).norm() > gap_limit || (c - b.start).norm() > gap_limit) return false;
    const Eigen::Vector2d ua = (a.start - c).normalized();
    const Eigen::Vector2d ub = (b.end - c).normalized();
    const double cos_angle = ua.dot(ub);
    if (cos_angle > cos_corner_min_ || cos_angle < cos_corner_max_) return false;
    // Near a door's jamb or its reveal (the jamb moved up to door_max_recess_m behind).
    bool near_door = false;
    for (std::size_t d = 0; d < num_doors && !near_door; ++d) {
      const Eigen::Vector2d back(std::cos(out[d].theta_rad), std::sin(out[d].theta_rad));
      for (const Eigen::Vector2d* jamb : {&out[d].jamb_a, &out[d].jamb_b}) {
        const double depth = std::clamp((c - *jamb).dot(back), 0.0, p.door_max_recess_m);
        near_door = near_door || (*jamb + depth * back - c).norm() <= p.corner_door_exclusion_m;
      }
    }
    if (near_door) return true;  // found, and part of a door
    // Concave when the sensor (at the origin) lies inside the angle of the two walls.
    const Eigen::Vector2d s = -c;
    const double ab = cross(ua, ub);
    const bool inside = ab > 0 ? (cross(ua, s) > 0 && cross(s, ub) > 0) : (cross(ua, s) < 0 && cross(s, ub) < 0);
    Eigen::Vector2d bisector = ua + ub;
    if (!inside) bisector = -bisector;

    Feature f;
    f.type = inside ? FeatureType::kCornerConcave : FeatureType::kCornerConvex;
    f.position = c;
    f.theta_rad = std::atan2(bisector.y(), bisector.x());
    f.jamb_a = a.start;
    f.jamb_b = b.end;
    const double arm_factor = std::min(1.0, std::min(a.length_m, b.length_m) / (2.0 * p.corner_min_arm_m));
    const double gap_factor = 1.0 - 0.5 * (b.start - a.end).norm() / p.corner_max_gap_m;
    f.confidence = std::clamp(arm_factor * gap_factor, 0.0, 1.0);
    // Covariance: n_k . dc + (t_k . c) dtheta_k = drho_k for both lines; the bisector turns
    // by the mean of the two lines' turns.
    Eigen::Matrix<double, 2, 4> rhs = Eigen::Matrix<double, 2, 4>::Zero();
    rhs(0, 0) = 1.0;
    rhs(0, 1) = -tangentOf(a).dot(c);
    rhs(1, 2) = 1.0;
    rhs(1, 3) = -tangentOf(b).dot(c);
    Eigen::Matrix<double, 3, 4> J = Eigen::Matrix<double, 3, 4>::Zero();
    J.topRows<2>() = Minv * rhs;
    J(2, 1) = 0.5;
    J(2, 3) = 0.5;
    Eigen::Matrix4d S = Eigen::Matrix4d::Zero();
    S.topLeftCorner<2, 2>() = a.covariance;
    S.bottomRightCorner<2, 2>() = b.covariance;
    f.covariance = J * S * J.transpose();
    f.segment_a = static_cast<std::uint32_t>(i);
    f.segment_b = static_cast<std::uint32_t>(j);
    out.push_back(f);
    return true;
  };
  for (std::size_t i = 0; i < pairs; ++i) {
    if (tryCorner(i, (i + 1) % n, 0.0)) continue;
    // Noise often leaves a short piece at the corner itself: step over one.
    const std::size_t mid = (i + 1) % n;
    const Segment& m = segs[mid];
    if (m.length_m < p.corner_min_arm_m && (i + 2 < n || segmentation.wraps_around) && n >= 3) {
      if (tryCorner(i, (i + 2) % n, m.length_m)) ++i;
    }
  }
}

}  // namespace lidarseg
