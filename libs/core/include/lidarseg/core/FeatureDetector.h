#pragma once
/// @file FeatureDetector.h
/// Doors and corners from the low-level (Wall-Danielsson) segments of a scan (paper §III.B).

#include <vector>

#include "lidarseg/core/Feature.h"
#include "lidarseg/core/Segmentation.h"

namespace lidarseg {

/// Every parameter of the door and corner detector. Keys in configuration files are the
/// field names ([features] section). Angles in degrees, lengths in metres.
struct FeatureDetectorParams {
  /// The cascade level whose segments are searched. The default, the first fusion, keeps
  /// every detail of the Wall-Danielsson segments (no erosion: door recesses and jambs
  /// stay) but repairs the walls that noise cut into pieces; kWallDanielsson uses the raw
  /// segments. The paper's "low-level segmentation" (§III.B).
  CascadeLevel level = CascadeLevel::kFused;

  // --- Corners: two segments, consecutive in scan order, whose facing endpoints are close
  // and whose lines meet at an angle in [corner_min_angle_deg, corner_max_angle_deg].
  /// Largest distance between the facing endpoints and from each to the lines'
  /// intersection (m).
  double corner_max_gap_m = 0.15;
  /// Range of the angle between the two walls (deg); 90 is a right-angled corner.
  double corner_min_angle_deg = 45.0;
  double corner_max_angle_deg = 135.0;
  /// Each wall of a corner at least this long (m) ...
  double corner_min_arm_m = 0.2;
  /// ... and made of at least this many points.
  std::size_t corner_min_points = 4;

  // --- Doors: a gap between two collinear wall segments.
  /// Range of door widths, jamb to jamb (m).
  double door_min_width_m = 0.6;
  double door_max_width_m = 2.1;
  /// The walls on both sides of the gap are parallel within this (deg) ...
  double door_collinear_angle_deg = 5.0;
  /// ... and each one's end lies within door_collinear_offset_m (a real wall's bow or step
  /// between two pieces, and where an end falls between two beams) plus door_noise_sigmas
  /// standard deviations of the scan's measured range noise seen at that end's incidence
  /// (sigma * cos(incidence)) of the other's line (m). Also joins the runs of segments the
  /// shallow-leaf pass reads.
  double door_collinear_offset_m = 0.04;
  /// Tolerances from the scan's noise are this many of its standard deviations: the
  /// collinearity above and the depth an ajar leaf's free end must reach behind the wall.
  double door_noise_sigmas = 3.0;
  /// Floor of the range noise measured on the scan (m): the median, over the walls of at
  /// least 10 points, of their residual scatter divided by the incidence (range noise moves
  /// a point along its beam); used alone when fewer than 3 walls measure it.
  double door_min_range_sigma_m = 0.01;
  /// Each wall beside the door at least this long (m) with at least this many points, or
  /// with as many as the beams leave on door_min_wall_m of it (1 + door_min_wall_m / the
  /// beam spacing r * dtheta / cos(incidence) there), but never fewer than
  /// door_min_sparse_wall_points (= door_min_wall_points: no allowance for sparse walls).
  double door_min_wall_m = 0.25;
  std::size_t door_min_wall_points = 4;
  std::size_t door_min_sparse_wall_points = 3;
  /// Fewer beams than this in the gap: no door (too far, or seen at a grazing angle).
  std::size_t door_min_gap_beams = 3;
  /// A gap is an opening only when it is at least this many times the spacing the scan's
  /// beams leave on the wall at either jamb (r * dtheta / cos(incidence), dtheta measured on
  /// the scan): a wall sampled sparsely at a grazing angle, or two beams in a row lost on
  /// it, leave gaps of one to three spacings.
  double door_gap_min_spacings = 3.0;
  /// Ranges on a grid: when at least this share of the ranges near a door (or a shallow
  /// leaf) lie on one grid of 1, 2, 5 or 10 cm (the largest such), the grid step q is part
  /// of the noise: a recess must exceed q cos(incidence) (quantised ranges make staircases
  /// of that depth on a plain wall) and q^2/12 adds to the range variance.
  double door_quantum_min_share = 0.5;
  /// A beam in the gap ending more than this in front of the wall line is an obstacle in
  /// the doorway; beyond door_max_occluded_fraction of them, the gap is no door (m).
  double door_front_tolerance_m = 0.1;
  double door_max_occluded_fraction = 0.2;
  /// Open door: at least this fraction of the gap's beams reach further than
  /// door_max_recess_m beyond the wall line. Beams without a return count as beyond, but
  /// only as many as the beams seen beyond: a lost return on a wall at a grazing angle looks
  /// like a beam through an opening, so lost returns alone are no door.
  double door_min_beyond_fraction = 0.7;
  /// Closed door: leaf segments parallel to the wall within door_leaf_parallel_deg,
  /// recessed behind the wall line by [door_min_recess_m, door_max_recess_m], together
  /// covering at least door_min_leaf_fraction of the gap's beams.
  double door_min_recess_m = 0.02;
  double door_max_recess_m = 0.3;
  double door_leaf_parallel_deg = 10.0;
  double door_min_leaf_fraction = 0.4;
  /// Door ajar: a leaf segment behind the wall, at more than door_leaf_parallel_deg to it,
  /// at least door_min_ajar_leaf_m long, with one end (the hinge) within
  /// door_hinge_tolerance_m of a jamb along the wall and at most door_max_recess_m (+ the
  /// tolerance) behind it: the hinges stand in the frame, which may be recessed. Its free
  /// end lies deeper than door_min_recess_m + door_noise_sigmas range sigmas (with the
  /// grid's q^2 / 12) x cos(incidence): a turned piece inside the noise band is the wall.
  double door_min_ajar_leaf_m = 0.2;
  double door_hinge_tolerance_m = 0.15;
  /// The reveals: the sides of the opening through a thick wall (or of a recess), from each
  /// jamb straight back by at most door_max_recess_m. Beams and segments within this of a
  /// jamb's reveal, along the wall, belong to the frame: they are neither doorway nor leaf
  /// (m). 3 sigma of the range noise plus the jamb's placement error.
  double door_reveal_tolerance_m = 0.06;
  /// Shallow closed doors: a leaf recessed by less than the segmenter's split threshold
  /// (a few range sigmas) stays inside its wall's segment. Within one run of collinear
  /// segments, a run of points door width long (between two steps found with
  /// door_shallow_window bins on each side, a bin being the points within
  /// door_min_wall_m / door_shallow_window along the wall, one point where the beams are
  /// sparser) lying [door_shallow_min_recess_m,
  /// door_shallow_max_recess_m] behind the wall points beside it, by at least
  /// door_shallow_min_sigmas standard errors of the difference of the two means (the
  /// scatter measured on the points themselves), is a closed door; one wall may hold
  /// several. door_shallow_min_sigmas 0: off.
  std::size_t door_shallow_window = 5;
  double door_shallow_min_sigmas = 5.0;
  /// Shallower offsets between two stretches of one wall are what a finished wall may do
  /// over a door's width and the walls beside it (building tolerances for the flatness of
  /// plastered walls: about 5 mm over 1 m and 10 mm over 4 m, DIN 18202 table 3), however
  /// significant the step is statistically (m).
  double door_shallow_min_recess_m = 0.01;
  /// Deeper steps are split off by the segmenter (its threshold is a few range sigmas, 5 cm
  /// at most for the profiles here) and found between two walls; a deeper "leaf" inside one
  /// segment is something else (m).
  double door_shallow_max_recess_m = 0.06;
  /// Beyond this angle between the wall's normal and the line of sight (deg) a shallow step
  /// is smeared over few far-apart points and its jambs are unsure: not reported.
  double door_shallow_max_incidence_deg = 60.0;
  /// Corners closer than this to a detected door's jamb or its reveal (door_max_recess_m
  /// behind the jamb) are part of the door and not reported (m).
  double corner_door_exclusion_m = 0.2;
  /// Collinear segments further apart in scan order than this are not paired as the two
  /// sides of a door (bounds the work per scan).
  std::size_t door_max_segments_between = 16;

  /// @throws std::invalid_argument naming the first bad key and its value.
  void validate() const;
};

/// Finds doors and corners in the detailed (low-level) segments of one scan.
///
/// Corners (convex or concave) come from consecutive segments, doors (open, closed in a
/// recess, ajar) from pairs of collinear segments with a gap of door width, classified by
/// the beams and segments inside the gap. Each feature carries a covariance propagated
/// from its segments' (rho, theta) covariances and the beam spacing at the jambs.
/// O(n * door_max_segments_between + beams) per scan, no allocation once `out` has grown.
class FeatureDetector {
 public:
  /// What the detector measures on each scan before applying its rules.
  struct ScanGeometry {
    /// Angle between neighbouring beams (rad); 0 when not measurable (rules using it off).
    double beam_step_rad = 0.0;
    /// Range noise measured on the scan's walls (m), at least door_min_range_sigma_m.
    double range_sigma_m = 0.0;
  };
  /// Measures the beam step and the range noise of one scan.
  ScanGeometry measure(const Segmentation& segmentation) const;
  /// The grid step (m) of the ranges of `count` beams from `first_beam` (NaN beams
  /// skipped), or 0 when fewer than door_quantum_min_share of them lie on one grid.
  double rangeQuantum(const Segmentation& segmentation, std::size_t first_beam, std::size_t count) const;

  /// @throws std::invalid_argument when a parameter is out of range.
  explicit FeatureDetector(const FeatureDetectorParams& params = {});

  /// Replaces `out` with the doors (first, in scan order) and corners of `segmentation`.
  /// Uses the segments of params().level and the points.
  void detect(const Segmentation& segmentation, std::vector<Feature>& out) const;
  /// Convenience overload returning a new vector.
  std::vector<Feature> detect(const Segmentation& segmentation) const;

  const FeatureDetectorParams& params() const { return params_; }

 private:
  void detectDoors(const Segmentation& segmentation, const ScanGeometry& geometry, std::vector<Feature>& out) const;
  void detectCorners(const Segmentation& segmentation, std::vector<Feature>& out) const;
  void detectShallowDoors(const Segmentation& segmentation, const ScanGeometry& geometry,
                          std::vector<Feature>& out) const;

  FeatureDetectorParams params_;
  // Derived from the parameters (cosines and sines of the angle thresholds).
  double cos_collinear_ = 0.0;
  double sin_leaf_parallel_ = 0.0;
  double cos_corner_min_ = 0.0;
  double cos_corner_max_ = 0.0;
  double cos_shallow_incidence_ = 0.0;
};

}  // namespace lidarseg
