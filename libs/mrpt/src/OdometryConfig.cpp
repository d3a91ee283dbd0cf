#include "lidarseg/mrpt/OdometryConfig.h"

#include "ConfigKeys.h"
#include "KeyTables.h"
#include "SectionLoaders.h"

namespace lidarseg::mrpt_adapter {

std::vector<std::string> matcherKeys() { return detail::keysOf<MatcherParams>(detail::MatcherKeys{}); }
std::vector<std::string> refinerKeys() { return detail::keysOf<RefinerParams>(detail::RefinerKeys{}); }
std::vector<std::string> searchKeys() { return detail::keysOf<SearchParams>(detail::SearchKeys{}); }
std::vector<std::string> odometryKeys() { return detail::keysOf<OdometryParams>(detail::OdometryKeys{}); }

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
  if (cfg.sectionExists(kRefinerSection)) {
    detail::loadKeys(loaded.refiner, cfg, kRefinerSection, source, lines(kRefinerSection),
                     detail::RefinerKeys{});
  }
  if (cfg.sectionExists(kSearchSection)) {
    detail::loadKeys(loaded.search, cfg, kSearchSection, source, lines(kSearchSection), detail::SearchKeys{});
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
  detail::saveKeys(params.refiner, cfg, kRefinerSection, detail::RefinerKeys{});
  detail::saveKeys(params.search, cfg, kSearchSection, detail::SearchKeys{});
  detail::saveKeys(params, cfg, kOdometrySection, detail::OdometryKeys{});
}

namespace detail {
void loadOdometrySections(OdometryParams& params, const LoadedConfig& file, const std::string& source) {
  loadAll(params, file.cfg, source, &file);
}
void loadStampSection(StampPolicyParams& params, const LoadedConfig& file, const std::string& source) {
  if (file.cfg.sectionExists(kStampsSection)) {
    loadKeys(params, file.cfg, kStampsSection, source, file.linesOf(kStampsSection), StampKeys{});
  }
}
}  // namespace detail

void saveStampPolicyParams(const StampPolicyParams& params, mrpt::config::CConfigFileBase& cfg) {
  detail::saveKeys(params, cfg, kStampsSection, detail::StampKeys{});
}

std::vector<std::string> stampKeys() { return detail::keysOf<StampPolicyParams>(detail::StampKeys{}); }

OdometryParams loadOdometryParamsFile(const std::string& path) {
  OdometryParams params;
  detail::loadOdometrySections(params, detail::readConfigFile(path), path);
  return params;
}

}  // namespace lidarseg::mrpt_adapter
