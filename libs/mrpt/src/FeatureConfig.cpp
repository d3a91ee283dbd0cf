#include "lidarseg/mrpt/FeatureConfig.h"

#include "ConfigKeys.h"
#include "KeyTables.h"
#include "SectionLoaders.h"

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

namespace detail {
void loadFeatureSection(FeatureDetectorParams& params, const LoadedConfig& file, const std::string& path) {
  if (file.cfg.sectionExists(kFeaturesSection)) {
    loadKeys(params, file.cfg, kFeaturesSection, path, file.linesOf(kFeaturesSection), FeatureKeys{});
  }
}
}  // namespace detail

FeatureDetectorParams loadFeatureDetectorParamsFile(const std::string& path) {
  FeatureDetectorParams params;
  detail::loadFeatureSection(params, detail::readConfigFile(path), path);
  return params;
}

}  // namespace lidarseg::mrpt_adapter
