#include "lidarseg/mrpt/OdometryConfig.h"

#include "ConfigKeys.h"
#include "KeyTables.h"

namespace lidarseg::mrpt_adapter {

std::vector<std::string> matcherKeys() { return detail::keysOf<MatcherParams>(detail::MatcherKeys{}); }
std::vector<std::string> odometryKeys() { return detail::keysOf<OdometryParams>(detail::OdometryKeys{}); }

void loadMatcherParams(MatcherParams& params, const mrpt::config::CConfigFileBase& cfg,
                       const std::string& section, const std::string& source) {
  detail::loadKeys(params, cfg, section, source, {}, detail::MatcherKeys{});
}

void saveMatcherParams(const MatcherParams& params, mrpt::config::CConfigFileBase& cfg,
                       const std::string& section) {
  detail::saveKeys(params, cfg, section, detail::MatcherKeys{});
}

namespace {
void loadAll(OdometryParams& params, const mrpt::config::CConfigFileBase& cfg, const std::string& source,
             const detail::LoadedConfig* file) {
  static const detail::LineMap kNoLines;
  const auto lines = [&](const std::string& s) -> const detail::LineMap& {
    return file ? file->linesOf(s) : kNoLines;
  };
  OdometryParams loaded = params;
  if (cfg.sectionExists(kSegmentationSection)) {
    detail::loadKeys(loaded.segmentation, cfg, kSegmentationSection, source, lines(kSegmentationSection),
                     detail::SegmentationKeys{});
  }
  if (cfg.sectionExists(kMatcherSection)) {
    detail::loadKeys(loaded.matcher, cfg, kMatcherSection, source, lines(kMatcherSection),
                     detail::MatcherKeys{});
  }
  if (cfg.sectionExists(kOdometrySection)) {
    detail::loadKeys(loaded, cfg, kOdometrySection, source, lines(kOdometrySection), detail::OdometryKeys{});
  }
  params = loaded;
}
}  // namespace

void loadOdometryParams(OdometryParams& params, const mrpt::config::CConfigFileBase& cfg,
                        const std::string& source) {
  loadAll(params, cfg, source, nullptr);
}

void saveOdometryParams(const OdometryParams& params, mrpt::config::CConfigFileBase& cfg) {
  detail::saveKeys(params.segmentation, cfg, kSegmentationSection, detail::SegmentationKeys{});
  detail::saveKeys(params.matcher, cfg, kMatcherSection, detail::MatcherKeys{});
  detail::saveKeys(params, cfg, kOdometrySection, detail::OdometryKeys{});
}

OdometryParams loadOdometryParamsFile(const std::string& path) {
  const detail::LoadedConfig file = detail::readConfigFile(path);
  OdometryParams params;
  loadAll(params, file.cfg, path, &file);
  return params;
}

}  // namespace lidarseg::mrpt_adapter
