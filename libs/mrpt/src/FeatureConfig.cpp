#include "lidarseg/mrpt/FeatureConfig.h"

#include "ConfigKeys.h"
#include "KeyTables.h"

namespace lidarseg::mrpt_adapter {

std::vector<std::string> featureKeys() {
  return detail::keysOf<FeatureDetectorParams>(detail::FeatureKeys{});
}

void loadFeatureDetectorParams(FeatureDetectorParams& params, const mrpt::config::CConfigFileBase& cfg,
                               const std::string& section, const std::string& source) {
  detail::loadKeys(params, cfg, section, source, {}, detail::FeatureKeys{});
}

void saveFeatureDetectorParams(const FeatureDetectorParams& params, mrpt::config::CConfigFileBase& cfg,
                               const std::string& section) {
  detail::saveKeys(params, cfg, section, detail::FeatureKeys{});
}

FeatureDetectorParams loadFeatureDetectorParamsFile(const std::string& path) {
  const detail::LoadedConfig file = detail::readConfigFile(path);
  FeatureDetectorParams params;
  if (file.cfg.sectionExists(kFeaturesSection)) {
    detail::loadKeys(params, file.cfg, kFeaturesSection, path, file.linesOf(kFeaturesSection),
                     detail::FeatureKeys{});
  }
  return params;
}

}  // namespace lidarseg::mrpt_adapter
