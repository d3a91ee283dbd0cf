#pragma once
// Private to lidarseg::mrpt: the key tables of the parameter structs (see ConfigKeys.h),
// shared by the configuration loaders and the alignment algorithm's TConfigParams.

#include "lidarseg/core/FeatureDetector.h"
#include "lidarseg/core/SegmentOdometry.h"
#include "lidarseg/core/StampPolicy.h"
#include "lidarseg/vision/CameraModel.h"
#include "lidarseg/vision/PeopleDetector.h"
#include "lidarseg/vision/RegionsOfInterest.h"

namespace lidarseg::mrpt_adapter::detail {

// Every key of the [segmentation] section and the field it sets.
struct SegmentationKeys {
  template <typename Params, typename Visitor>
  void operator()(Params& p, Visitor&& visit) const {
    visit("range_sigma_m", p.noise.range_sigma_m);
    visit("bearing_sigma_rad", p.noise.bearing_sigma_rad);
    visit("wd_threshold_m", p.wall_danielsson.threshold_m);
    visit("wd_max_range_jump_m", p.wall_danielsson.max_range_jump_m);
    visit("wd_max_range_jump_ratio", p.wall_danielsson.max_range_jump_ratio);
    visit("wd_min_points", p.wall_danielsson.min_points);
    visit("fusion1_max_angle_rad", p.cascade.first_fusion.max_angle_rad);
    visit("fusion1_max_line_distance_m", p.cascade.first_fusion.max_line_distance_m);
    visit("fusion1_max_gap_m", p.cascade.first_fusion.max_gap_m);
    visit("fusion1_noise_gate_sigmas", p.cascade.first_fusion.noise_gate_sigmas);
    visit("erosion_min_length_m", p.cascade.erosion.min_length_m);
    visit("erosion_min_points", p.cascade.erosion.min_points);
    visit("fusion2_max_angle_rad", p.cascade.second_fusion.max_angle_rad);
    visit("fusion2_max_line_distance_m", p.cascade.second_fusion.max_line_distance_m);
    visit("fusion2_max_gap_m", p.cascade.second_fusion.max_gap_m);
    visit("fusion2_noise_gate_sigmas", p.cascade.second_fusion.noise_gate_sigmas);
  }
};

// Every key of the [matcher] section.
struct MatcherKeys {
  template <typename Params, typename Visitor>
  void operator()(Params& p, Visitor&& visit) const {
    visit("cog_gate_m", p.cog_gate_m);
    visit("cog_gate_length_ratio", p.cog_gate_length_ratio);
    visit("rho_scale_m", p.rho_scale_m);
    visit("theta_scale_rad", p.theta_scale_rad);
    visit("cog_scale_m", p.cog_scale_m);
    visit("length_weight", p.length_weight);
    visit("max_weight", p.max_weight);
    visit("ambiguity_ratio", p.ambiguity_ratio);
    visit("band_half_width", p.band_half_width);
    visit("min_matches", p.min_matches);
    visit("iterations", p.iterations);
    visit("max_segments", p.max_segments);
    visit("outlier_sigmas", p.outlier_sigmas);
    visit("degeneracy_ratio", p.degeneracy_ratio);
    visit("unconstrained_sigma_m", p.unconstrained_sigma_m);
    visit("min_rho_sigma_m", p.min_rho_sigma_m);
    visit("min_theta_sigma_rad", p.min_theta_sigma_rad);
  }
};

// Every key of the [odometry] section (the matcher's and segmentation's have their own).
struct OdometryKeys {
  template <typename Params, typename Visitor>
  void operator()(Params& p, Visitor&& visit) const {
    visit("level", p.level);
    visit("degenerate_fallback_level", p.degenerate_fallback_level);
    visit("keyframe_distance_m", p.keyframe_distance_m);
    visit("keyframe_angle_rad", p.keyframe_angle_rad);
    visit("deskew", p.deskew);
    visit("velocity_window_s", p.velocity_window_s);
    visit("angular_velocity_window_s", p.angular_velocity_window_s);
    visit("deskew_tolerance_rad", p.deskew_tolerance_rad);
    visit("estimate_sweep_rate", p.estimate_sweep_rate);
    visit("scanner_rotation_hz", p.scanner_rotation_hz);
    visit("scan_stamp", p.scan_stamp);
    visit("recovery", p.recovery);
    visit("doubtful_ratio", p.doubtful_ratio);
    visit("prior_preference", p.prior_preference);
    visit("search_preference", p.search_preference);
    visit("search_when_doubtful", p.search_when_doubtful);
    visit("revise_keyframe", p.revise_keyframe);
    visit("deskew_covariance", p.deskew_covariance);
    visit("wide_search_factor", p.wide_search_factor);
    visit("check_match_against_prior", p.check_match_against_prior);
    visit("degenerate_along_prior", p.degenerate_along_prior);
    visit("degenerate_keeps_velocity", p.degenerate_keeps_velocity);
    visit("prior_gate_sigmas", p.prior_gate_sigmas);
    visit("prior_accel_m_s2", p.prior_accel_m_s2);
    visit("prior_angular_accel_rad_s2", p.prior_angular_accel_rad_s2);
    visit("odometry_error_ratio", p.odometry_error_ratio);
    visit("prior_gate_floor_rad", p.prior_gate_floor_rad);
    visit("local_map_keyframes", p.local_map_keyframes);
  }
};

// Every key of the [stamps] section (how a run repairs a log's stamps).
struct StampKeys {
  template <typename Params, typename Visitor>
  void operator()(Params& p, Visitor&& visit) const {
    visit("max_time_gap_s", p.max_time_gap_s);
    visit("max_speed_mps", p.max_speed_mps);
    visit("max_turn_rate_radps", p.max_turn_rate_radps);
    visit("unusable_step_span_s", p.unusable_step_span_s);
    visit("min_span_s", p.min_span_s);
    visit("jump_margin", p.jump_margin);
    visit("output_nudge_s", p.output_nudge_s);
  }
};

// Every key of the [refiner] section (point-to-segment refinement).
struct RefinerKeys {
  template <typename Params, typename Visitor>
  void operator()(Params& p, Visitor&& visit) const {
    visit("enabled", p.enabled);
    visit("level", p.level);
    visit("min_segment_points", p.min_segment_points);
    visit("unsegmented_points", p.unsegmented_points);
    visit("max_iterations", p.max_iterations);
    visit("max_distance_m", p.max_distance_m);
    visit("robust_scale_m", p.robust_scale_m);
    visit("initial_scale_m", p.initial_scale_m);
    visit("endpoint_margin_m", p.endpoint_margin_m);
    visit("bearing_window", p.bearing_window);
    visit("min_point_sigma_m", p.min_point_sigma_m);
    visit("model_sigma_m", p.model_sigma_m);
    visit("model_sigma_rad", p.model_sigma_rad);
    visit("correlation_length_points", p.correlation_length_points);
    visit("min_inlier_ratio", p.min_inlier_ratio);
    visit("max_points", p.max_points);
    visit("min_points", p.min_points);
    visit("min_constraint_points", p.min_constraint_points);
    visit("degeneracy_ratio", p.degeneracy_ratio);
    visit("unconstrained_sigma_m", p.unconstrained_sigma_m);
    visit("convergence_m", p.convergence_m);
    visit("reassociate_m", p.reassociate_m);
  }
};

// Every key of the [search] section (correlative recovery search).
struct SearchKeys {
  template <typename Params, typename Visitor>
  void operator()(Params& p, Visitor&& visit) const {
    visit("linear_window_m", p.linear_window_m);
    visit("angular_window_rad", p.angular_window_rad);
    visit("resolution_m", p.resolution_m);
    visit("sigma_m", p.sigma_m);
    visit("angular_step_rad", p.angular_step_rad);
    visit("max_points", p.max_points);
    visit("coarse_cells", p.coarse_cells);
    visit("max_grid_cells", p.max_grid_cells);
  }
};

// Every key of the [features] section (door and corner detector).
struct FeatureKeys {
  template <typename Params, typename Visitor>
  void operator()(Params& p, Visitor&& visit) const {
    visit("level", p.level);
    visit("corner_max_gap_m", p.corner_max_gap_m);
    visit("corner_min_angle_deg", p.corner_min_angle_deg);
    visit("corner_max_angle_deg", p.corner_max_angle_deg);
    visit("corner_min_arm_m", p.corner_min_arm_m);
    visit("corner_min_points", p.corner_min_points);
    visit("door_min_width_m", p.door_min_width_m);
    visit("door_max_width_m", p.door_max_width_m);
    visit("door_collinear_angle_deg", p.door_collinear_angle_deg);
    visit("door_collinear_offset_m", p.door_collinear_offset_m);
    visit("door_noise_sigmas", p.door_noise_sigmas);
    visit("door_min_range_sigma_m", p.door_min_range_sigma_m);
    visit("door_min_wall_m", p.door_min_wall_m);
    visit("door_min_wall_points", p.door_min_wall_points);
    visit("door_min_sparse_wall_points", p.door_min_sparse_wall_points);
    visit("door_min_gap_beams", p.door_min_gap_beams);
    visit("door_gap_min_spacings", p.door_gap_min_spacings);
    visit("door_quantum_min_share", p.door_quantum_min_share);
    visit("door_front_tolerance_m", p.door_front_tolerance_m);
    visit("door_max_occluded_fraction", p.door_max_occluded_fraction);
    visit("door_min_beyond_fraction", p.door_min_beyond_fraction);
    visit("door_min_recess_m", p.door_min_recess_m);
    visit("door_max_recess_m", p.door_max_recess_m);
    visit("door_leaf_parallel_deg", p.door_leaf_parallel_deg);
    visit("door_min_leaf_fraction", p.door_min_leaf_fraction);
    visit("door_min_ajar_leaf_m", p.door_min_ajar_leaf_m);
    visit("door_hinge_tolerance_m", p.door_hinge_tolerance_m);
    visit("door_reveal_tolerance_m", p.door_reveal_tolerance_m);
    visit("door_shallow_window", p.door_shallow_window);
    visit("door_shallow_min_sigmas", p.door_shallow_min_sigmas);
    visit("door_shallow_min_recess_m", p.door_shallow_min_recess_m);
    visit("door_shallow_max_recess_m", p.door_shallow_max_recess_m);
    visit("door_shallow_max_incidence_deg", p.door_shallow_max_incidence_deg);
    visit("corner_door_exclusion_m", p.corner_door_exclusion_m);
    visit("door_max_segments_between", p.door_max_segments_between);
  }
};

// Every key of the [camera] section: image size, K, distortion, pose in the lidar frame.
struct CameraKeys {
  template <typename Params, typename Visitor>
  void operator()(Params& p, Visitor&& visit) const {
    visit("width", p.width);
    visit("height", p.height);
    visit("fx", p.fx);
    visit("fy", p.fy);
    visit("cx", p.cx);
    visit("cy", p.cy);
    visit("k1", p.k1);
    visit("k2", p.k2);
    visit("p1", p.p1);
    visit("p2", p.p2);
    visit("k3", p.k3);
    visit("x_m", p.x_m);
    visit("y_m", p.y_m);
    visit("z_m", p.z_m);
    visit("yaw_rad", p.yaw_rad);
    visit("pitch_rad", p.pitch_rad);
    visit("roll_rad", p.roll_rad);
  }
};

// Every key of the [rois] section: how a feature becomes a box.
struct RoiKeys {
  template <typename Params, typename Visitor>
  void operator()(Params& p, Visitor&& visit) const {
    visit("lidar_height_m", p.lidar_height_m);
    visit("door_height_m", p.door_height_m);
    visit("corner_strip_m", p.corner_strip_m);
    visit("corner_height_m", p.corner_height_m);
    visit("min_size_px", p.min_size_px);
  }
};

// Every key of the [people] section: the HOG detector and its crops.
struct PeopleKeys {
  template <typename Params, typename Visitor>
  void operator()(Params& p, Visitor&& visit) const {
    visit("hit_threshold", p.hit_threshold);
    visit("win_stride_px", p.win_stride_px);
    visit("scale_step", p.scale_step);
    visit("group_threshold", p.group_threshold);
    visit("roi_margin", p.roi_margin);
    visit("image_scale", p.image_scale);
  }
};

}  // namespace lidarseg::mrpt_adapter::detail
