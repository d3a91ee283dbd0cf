#include "lidarseg/mrpt/LidarsegConfig.h"

#include <algorithm>
#include <sstream>
#include <stdexcept>

#include "ConfigKeys.h"
#include "SectionLoaders.h"

namespace lidarseg::mrpt_adapter {

namespace {

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

// The 1-based line where `section` starts ("[name]" in INI, "name:" at the top level of
// YAML), 0 when not found.
int sectionLine(const detail::LoadedConfig& file, const std::string& section) {
  std::istringstream in(file.text);
  std::string line;
  const std::string name = lower(section);
  for (int number = 1; std::getline(in, line); ++number) {
    std::string t = line;
    t.erase(0, t.find_first_not_of(" \t"));
    if (file.yaml) {
      if (line.empty() || line[0] == ' ' || line[0] == '\t') continue;
      const auto colon = t.find(':');
      if (colon != std::string::npos && lower(t.substr(0, colon)) == name) return number;
    } else if (!t.empty() && t[0] == '[') {
      const auto close = t.find(']');
      if (close != std::string::npos && lower(t.substr(1, close - 1)) == name) return number;
    }
  }
  return 0;
}

void rejectUnknownSections(const detail::LoadedConfig& file, const std::string& path) {
  std::vector<std::string> sections;
  file.cfg.getAllSections(sections);
  const auto& known = LidarsegConfig::knownSections();
  for (const std::string& s : sections) {
    if (s.empty()) continue;  // keys before any section (MRPT's INI allows them)
    if (std::find(known.begin(), known.end(), lower(s)) != known.end()) continue;
    const int line = sectionLine(file, s);
    std::string list;
    for (const auto& k : known) list += (list.empty() ? "" : ", ") + k;
    throw std::invalid_argument(path + (line > 0 ? ":" + std::to_string(line) : std::string()) +
                                ": unknown section [" + s + "] (known: " + list + ")");
  }
}

}  // namespace

const std::vector<std::string>& LidarsegConfig::knownSections() {
  static const std::vector<std::string> kKnown = {"segmentation", "matcher", "refiner", "search", "odometry",
                                                  "stamps", "features", "camera", "rois", "people",
                                                  "icp", "simulation"};
  return kKnown;
}

LidarsegConfig LidarsegConfig::loadFile(const std::string& path) {
  const detail::LoadedConfig file = detail::readConfigFile(path);
  rejectUnknownSections(file, path);
  LidarsegConfig c;
  detail::loadOdometrySections(c.odometry, file, path);
  detail::loadStampSection(c.stamps, file, path);
  detail::loadFeatureSection(c.features, file, path);
  detail::loadVisionSections(c.vision, file, path);
  if (file.cfg.sectionExists("icp")) c.icp.loadFromConfigFile(file.cfg, "icp");
  return c;
}

}  // namespace lidarseg::mrpt_adapter
