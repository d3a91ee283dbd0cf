#include "lidarseg/mrpt/SegmentationConfig.h"

#include "ConfigKeys.h"

namespace lidarseg::mrpt_adapter {

namespace {
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
}  // namespace

std::vector<std::string> segmentationKeys() {
  return detail::keysOf<SegmentationParams>(SegmentationKeys{});
}

void loadSegmentationParams(SegmentationParams& params, const mrpt::config::CConfigFileBase& cfg,
                            const std::string& section, const std::string& source) {
  detail::loadKeys(params, cfg, section, source, {}, SegmentationKeys{});
}

void saveSegmentationParams(const SegmentationParams& params, mrpt::config::CConfigFileBase& cfg,
                            const std::string& section) {
  detail::saveKeys(params, cfg, section, SegmentationKeys{});
}

SegmentationParams loadSegmentationParamsFile(const std::string& path, const std::string& section) {
  const detail::LoadedConfig file = detail::readConfigFile(path);
  SegmentationParams params;
  detail::loadKeys(params, file.cfg, section, path, file.linesOf(section),
                   SegmentationKeys{});
  return params;
}

}  // namespace lidarseg::mrpt_adapter
