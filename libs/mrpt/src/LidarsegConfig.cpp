#include "lidarseg/mrpt/LidarsegConfig.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include <mrpt/core/bits_math.h>

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

// [icp]: the keys mrpt::slam::CICP::TConfigParams::loadFromConfigFile reads (MRPT 2.5),
// each parsed strictly and checked for range here, then set on the struct (MRPT's own reader
// takes "nan", reads "1e3" as 1 and "-5" as 4294967291, and ignores unknown keys; issue 16).
struct IcpKey {
  const char* name;
  enum Kind { kCount, kReal, kBool, kAlgorithm, kCovariance } kind;
  double lo, hi;
  bool lo_open;  // the range excludes lo
};

constexpr IcpKey kIcpKeys[] = {
    {"maxIterations", IcpKey::kCount, 1, 1000, false},
    {"minAbsStep_trans", IcpKey::kReal, 0, 1e3, false},
    {"minAbsStep_rot", IcpKey::kReal, 0, 3.15, false},
    {"ICP_algorithm", IcpKey::kAlgorithm, 0, 0, false},
    {"ICP_covariance_method", IcpKey::kCovariance, 0, 0, false},
    {"thresholdDist", IcpKey::kReal, 0, 1e3, true},
    {"thresholdAng_DEG", IcpKey::kReal, 0, 180, false},
    {"ALFA", IcpKey::kReal, 0, 1, true},
    {"smallestThresholdDist", IcpKey::kReal, 0, 1e3, false},
    {"onlyUniqueRobust", IcpKey::kBool, 0, 0, false},
    {"doRANSAC", IcpKey::kBool, 0, 0, false},
    {"covariance_varPoints", IcpKey::kReal, 0, 1e6, true},
    {"ransac_minSetSize", IcpKey::kCount, 1, 1000, false},
    {"ransac_maxSetSize", IcpKey::kCount, 1, 1000, false},
    {"ransac_mahalanobisDistanceThreshold", IcpKey::kReal, 0, 1e6, true},
    {"ransac_nSimulations", IcpKey::kCount, 0, 100000, false},
    {"normalizationStd", IcpKey::kReal, 0, 1e3, true},
    {"ransac_fuseByCorrsMatch", IcpKey::kBool, 0, 0, false},
    {"ransac_fuseMaxDiffXY", IcpKey::kReal, 0, 1e3, false},
    {"ransac_fuseMaxDiffPhi_DEG", IcpKey::kReal, 0, 180, false},
    {"kernel_rho", IcpKey::kReal, 0, 1e3, true},
    {"use_kernel", IcpKey::kBool, 0, 0, false},
    {"Axy_aprox_derivatives", IcpKey::kReal, 0, 1e3, true},
    {"LM_initial_lambda", IcpKey::kReal, 0, 1e6, true},
    {"skip_cov_calculation", IcpKey::kBool, 0, 0, false},
    {"skip_quality_calculation", IcpKey::kBool, 0, 0, false},
    {"corresponding_points_decimation", IcpKey::kCount, 1, 1000, false},
};

std::string rangeText(const IcpKey& k) {
  std::ostringstream os;
  os << (k.lo_open ? "(" : "[") << k.lo << ", " << k.hi << "]";
  return os.str();
}

void loadIcpSection(mrpt::slam::CICP::TConfigParams& icp, const detail::LoadedConfig& file,
                    const std::string& source) {
  const std::string section = "icp";
  if (!file.cfg.sectionExists(section)) return;
  const detail::LineMap& lines = file.linesOf(section);
  std::vector<std::string> present;
  file.cfg.getAllKeys(section, present);
  for (const std::string& key : present) {
    const bool known = std::any_of(std::begin(kIcpKeys), std::end(kIcpKeys),
                                   [&](const IcpKey& k) { return key == k.name; });
    if (known) continue;
    std::string hint;
    if (key == "thresholdAng" || key == "ransac_fuseMaxDiffPhi") {
      hint = " (MRPT reads this angle in degrees as " + key + "_DEG)";
    }
    throw std::invalid_argument(detail::where(source, lines, section, key) + ": unknown key" + hint +
                                " (the keys of mrpt::slam::CICP::TConfigParams)");
  }
  mrpt::slam::CICP::TConfigParams loaded = icp;
  for (const IcpKey& k : kIcpKeys) {
    if (!file.cfg.keyExists(section, k.name)) continue;
    const std::string text = file.cfg.read_string(section, k.name, "");
    const std::string at = detail::where(source, lines, section, k.name);
    const std::string name = k.name;
    if (k.kind == IcpKey::kBool) {
      const std::string t = lower(text);
      bool v = false;
      if (t == "1" || t == "true" || t == "yes") {
        v = true;
      } else if (!(t == "0" || t == "false" || t == "no")) {
        throw std::invalid_argument(at + ": '" + text + "' is not 0 or 1 (true or false)");
      }
      if (name == "onlyUniqueRobust") loaded.onlyUniqueRobust = v;
      if (name == "doRANSAC") loaded.doRANSAC = v;
      if (name == "ransac_fuseByCorrsMatch") loaded.ransac_fuseByCorrsMatch = v;
      if (name == "use_kernel") loaded.use_kernel = v;
      if (name == "skip_cov_calculation") loaded.skip_cov_calculation = v;
      if (name == "skip_quality_calculation") loaded.skip_quality_calculation = v;
      continue;
    }
    if (k.kind == IcpKey::kAlgorithm || k.kind == IcpKey::kCovariance) {
      const bool algorithm = k.kind == IcpKey::kAlgorithm;
      const char* names[2] = {algorithm ? "icpClassic" : "icpCovLinealMSE",
                              algorithm ? "icpLevenbergMarquardt" : "icpCovFiniteDifferences"};
      int v = -1;
      for (int n = 0; n < 2; ++n) {
        if (lower(text) == lower(names[n]) || text == std::to_string(n)) v = n;
      }
      if (v < 0) {
        throw std::invalid_argument(at + ": '" + text + "' is not one of " + names[0] + ", " + names[1]);
      }
      if (algorithm) {
        loaded.ICP_algorithm = static_cast<mrpt::slam::TICPAlgorithm>(v);
      } else {
        loaded.ICP_covariance_method = static_cast<mrpt::slam::TICPCovarianceMethod>(v);
      }
      continue;
    }
    const double v = k.kind == IcpKey::kCount ? static_cast<double>(detail::parseCount(text, at))
                                              : detail::parseDouble(text, at);
    if (!(std::isfinite(v) && (k.lo_open ? v > k.lo : v >= k.lo) && v <= k.hi)) {
      throw std::invalid_argument(at + ": '" + text + "' is out of range: " + name + " must be " +
                                  (k.kind == IcpKey::kCount ? "a whole number " : "finite and ") + "in " +
                                  rangeText(k));
    }
    const auto count = static_cast<unsigned int>(v);
    if (name == "maxIterations") loaded.maxIterations = count;
    if (name == "minAbsStep_trans") loaded.minAbsStep_trans = v;
    if (name == "minAbsStep_rot") loaded.minAbsStep_rot = v;
    if (name == "thresholdDist") loaded.thresholdDist = v;
    if (name == "thresholdAng_DEG") loaded.thresholdAng = mrpt::DEG2RAD(v);  // as CICP's own loader
    if (name == "ALFA") loaded.ALFA = v;
    if (name == "smallestThresholdDist") loaded.smallestThresholdDist = v;
    if (name == "covariance_varPoints") loaded.covariance_varPoints = v;
    if (name == "ransac_minSetSize") loaded.ransac_minSetSize = count;
    if (name == "ransac_maxSetSize") loaded.ransac_maxSetSize = count;
    if (name == "ransac_mahalanobisDistanceThreshold") loaded.ransac_mahalanobisDistanceThreshold = v;
    if (name == "ransac_nSimulations") loaded.ransac_nSimulations = count;
    if (name == "normalizationStd") loaded.normalizationStd = v;
    if (name == "ransac_fuseMaxDiffXY") loaded.ransac_fuseMaxDiffXY = v;
    if (name == "ransac_fuseMaxDiffPhi_DEG") loaded.ransac_fuseMaxDiffPhi = mrpt::DEG2RAD(v);
    if (name == "kernel_rho") loaded.kernel_rho = v;
    if (name == "Axy_aprox_derivatives") loaded.Axy_aprox_derivatives = v;
    if (name == "LM_initial_lambda") loaded.LM_initial_lambda = v;
    if (name == "corresponding_points_decimation") loaded.corresponding_points_decimation = count;
  }
  const std::size_t min_set = loaded.ransac_minSetSize, max_set = loaded.ransac_maxSetSize;
  if (min_set > max_set) {
    // Named at the key the file gives (the maximum when it gives both).
    const char* key = file.cfg.keyExists(section, "ransac_maxSetSize") ? "ransac_maxSetSize" : "ransac_minSetSize";
    throw std::invalid_argument(detail::where(source, lines, section, key) +
                                ": ransac_maxSetSize must be >= ransac_minSetSize (" + std::to_string(max_set) +
                                " < " + std::to_string(min_set) + ")");
  }
  icp = loaded;
}

}  // namespace

const std::vector<std::string>& LidarsegConfig::knownSections() {
  static const std::vector<std::string> kKnown = {"segmentation", "matcher", "refiner", "search", "odometry",
                                                  "stamps", "features", "camera", "rois", "people",
                                                  "icp", "simulation"};
  return kKnown;
}

mrpt::slam::CICP::TConfigParams LidarsegConfig::baselineIcpDefaults() {
  mrpt::slam::CICP::TConfigParams p;
  p.corresponding_points_decimation = 1;
  p.thresholdDist = 0.5;
  p.maxIterations = 60;
  return p;
}

LidarsegConfig LidarsegConfig::loadFile(const std::string& path) {
  const detail::LoadedConfig file = detail::readConfigFile(path);
  rejectUnknownSections(file, path);
  LidarsegConfig c;
  detail::loadOdometrySections(c.odometry, file, path);
  detail::loadStampSection(c.stamps, file, path);
  detail::loadFeatureSection(c.features, file, path);
  detail::loadVisionSections(c.vision, file, path);
  loadIcpSection(c.icp, file, path);
  return c;
}

}  // namespace lidarseg::mrpt_adapter
