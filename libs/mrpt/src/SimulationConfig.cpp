#include "lidarseg/mrpt/SimulationConfig.h"

#include "ConfigKeys.h"

namespace lidarseg::mrpt_adapter {

namespace {
struct SimulationKeys {
  template <typename Params, typename Visitor>
  void operator()(Params& p, Visitor&& visit) const {
    visit("num_beams", p.num_beams);
    visit("field_of_view_rad", p.field_of_view_rad);
    visit("range_sigma_m", p.sensor.range_sigma_m);
    visit("far_range_m", p.sensor.far_range_m);
    visit("far_range_sigma_m", p.sensor.far_range_sigma_m);
    visit("max_range_m", p.sensor.max_range_m);
    visit("frequency_hz", p.sensor.frequency_hz);
    visit("rolling_shutter", p.rolling_shutter);
    visit("scan_stamp", p.scan_stamp);
    visit("lidar_z_m", p.lidar_z_m);
    visit("camera_every_scans", p.camera_every_scans);
    visit("camera_width", p.camera.width);
    visit("camera_height", p.camera.height);
    visit("camera_fx", p.camera.fx);
    visit("camera_fy", p.camera.fy);
    visit("camera_cx", p.camera.cx);
    visit("camera_cy", p.camera.cy);
    visit("camera_x_m", p.camera.x_m);
    visit("camera_y_m", p.camera.y_m);
    visit("camera_z_m", p.camera.z_m);
    visit("camera_yaw_rad", p.camera.yaw_rad);
    visit("wall_height_m", p.heights.wall_m);
    visit("door_height_m", p.heights.door_m);
    visit("odom_translation_per_m", p.odometry.translation_per_m);
    visit("odom_rotation_per_rad", p.odometry.rotation_per_rad);
    visit("odom_rotation_per_m", p.odometry.rotation_per_m);
    visit("start_time_s", p.start_time_s);
  }
};
}  // namespace

std::vector<std::string> simulationKeys() {
  return detail::keysOf<sim::SimulationParams>(SimulationKeys{});
}

void loadSimulationParams(sim::SimulationParams& params, const mrpt::config::CConfigFileBase& cfg,
                          const std::string& section, const std::string& source) {
  detail::loadKeys(params, cfg, section, source, {}, SimulationKeys{});
}

void saveSimulationParams(const sim::SimulationParams& params, mrpt::config::CConfigFileBase& cfg,
                          const std::string& section) {
  detail::saveKeys(params, cfg, section, SimulationKeys{});
}

void loadSimulationParamsFile(sim::SimulationParams& params, const std::string& path,
                              const std::string& section) {
  const detail::LoadedConfig file = detail::readConfigFile(path);
  detail::loadKeys(params, file.cfg, section, path, file.linesOf(section),
                   SimulationKeys{});
}

}  // namespace lidarseg::mrpt_adapter
