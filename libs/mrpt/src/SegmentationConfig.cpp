#include "lidarseg/mrpt/SegmentationConfig.h"

#include "ConfigKeys.h"
#include "KeyTables.h"

namespace lidarseg::mrpt_adapter {


std::vector<std::string> segmentationKeys() {
  return detail::keysOf<SegmentationParams>(detail::SegmentationKeys{});
}

void loadSegmentationParams(SegmentationParams& params, const mrpt::config::CConfigFileBase& cfg,
                            const std::string& section, const std::string& source) {
  detail::loadKeys(params, cfg, section, source, {}, detail::SegmentationKeys{});
}

void saveSegmentationParams(const SegmentationParams& params, mrpt::config::CConfigFileBase& cfg,
                            const std::string& section) {
  detail::saveKeys(params, cfg, section, detail::SegmentationKeys{});
}

SegmentationParams loadSegmentationParamsFile(const std::string& path, const std::string& section) {
  const detail::LoadedConfig file = detail::readConfigFile(path);
  SegmentationParams params;
  detail::loadKeys(params, file.cfg, section, path, file.linesOf(section),
                   detail::SegmentationKeys{});
  return params;
}

}  // namespace lidarseg::mrpt_adapter
