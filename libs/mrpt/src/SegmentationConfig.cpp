#include "lidarseg/mrpt/SegmentationConfig.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iomanip>
#include <limits>
#include <map>
#include <sstream>
#include <stdexcept>

#include <mrpt/config/CConfigFileMemory.h>

namespace lidarseg::mrpt_adapter {

namespace {

// Visits every (key, field) of the parameters; the single table behind load, save and the
// unknown-key check. `visit` is called as visit(key, double&) or visit(key, std::size_t&).
template <typename Params, typename Visitor>
void forEachKey(Params& p, Visitor&& visit) {
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

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r\n");
  if (b == std::string::npos) return {};
  const auto e = s.find_last_not_of(" \t\r\n");
  return s.substr(b, e - b + 1);
}

using LineMap = std::map<std::string, int>;

// "file.ini:12 [section] key", or without ":line" when the line is not known.
std::string where(const std::string& source, const LineMap& lines, const std::string& section,
                  const std::string& key) {
  const auto it = lines.find(key);
  const std::string at = it == lines.end() ? source : source + ":" + std::to_string(it->second);
  return at + " [" + section + "] " + key;
}

// Line numbers (1-based) of the keys of `section` in an INI or YAML text, for messages.
LineMap keyLines(const std::string& text, const std::string& section, bool yaml) {
  LineMap lines;
  std::istringstream in(text);
  std::string line;
  std::string current;
  for (int number = 1; std::getline(in, line); ++number) {
    const std::string t = [&] {
      std::string u = line;
      const auto b = u.find_first_not_of(" \t\r");
      return b == std::string::npos ? std::string() : u.substr(b);
    }();
    if (t.empty() || t[0] == '#' || t[0] == ';' || t.rfind("//", 0) == 0) continue;
    const bool indented = !line.empty() && (line[0] == ' ' || line[0] == '\t');
    if (!yaml && t[0] == '[') {
      current = t.substr(1, t.find(']') - 1);
      continue;
    }
    const auto sep = t.find(yaml ? ':' : '=');
    if (sep == std::string::npos) continue;
    std::string key = t.substr(0, sep);
    key.erase(key.find_last_not_of(" \t") + 1);
    if (yaml && !indented) {
      current = key;
      continue;
    }
    if (current == section && !lines.count(key)) lines[key] = number;
  }
  return lines;
}

void loadImpl(SegmentationParams& params, const mrpt::config::CConfigFileBase& cfg,
              const std::string& section, const std::string& source, const LineMap& lines);

double parseDouble(const std::string& text, const std::string& context) {
  const std::string t = trim(text);
  errno = 0;
  char* end = nullptr;
  const double v = std::strtod(t.c_str(), &end);
  if (t.empty() || end != t.c_str() + t.size() || errno == ERANGE) {
    throw std::invalid_argument(context + ": '" + text + "' is not a number");
  }
  return v;
}

std::size_t parseCount(const std::string& text, const std::string& context) {
  const double v = parseDouble(text, context);
  if (!(v >= 0.0) || v != std::floor(v) || v > 1e9) {
    throw std::invalid_argument(context + ": '" + text + "' is not a whole number >= 0");
  }
  return static_cast<std::size_t>(v);
}

bool endsWith(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() &&
         std::equal(suffix.rbegin(), suffix.rend(), s.rbegin(),
                    [](char a, char b) { return std::tolower(a) == std::tolower(b); });
}

}  // namespace

std::vector<std::string> segmentationKeys() {
  std::vector<std::string> keys;
  SegmentationParams p;
  forEachKey(p, [&](const char* key, auto&) { keys.emplace_back(key); });
  return keys;
}

void loadSegmentationParams(SegmentationParams& params, const mrpt::config::CConfigFileBase& cfg,
                            const std::string& section, const std::string& source) {
  loadImpl(params, cfg, section, source, {});
}

namespace {
void loadImpl(SegmentationParams& params, const mrpt::config::CConfigFileBase& cfg,
              const std::string& section, const std::string& source, const LineMap& lines) {
  const std::vector<std::string> known = segmentationKeys();
  std::vector<std::string> present;
  cfg.getAllKeys(section, present);
  for (const std::string& key : present) {
    if (std::find(known.begin(), known.end(), key) == known.end()) {
      throw std::invalid_argument(where(source, lines, section, key) + ": unknown key");
    }
  }
  SegmentationParams loaded = params;
  forEachKey(loaded, [&](const char* key, auto& field) {
    if (!cfg.keyExists(section, key)) return;
    const std::string text = cfg.read_string(section, key, "");
    using Field = std::decay_t<decltype(field)>;
    if constexpr (std::is_same_v<Field, double>) {
      field = parseDouble(text, where(source, lines, section, key));
    } else {
      field = parseCount(text, where(source, lines, section, key));
    }
  });
  try {
    loaded.validate();
  } catch (const std::invalid_argument& e) {
    // validate() messages start with the offending key.
    const std::string message = e.what();
    const std::string key = message.substr(0, message.find(' '));
    throw std::invalid_argument(where(source, lines, section, key) + ": " + message);
  }
  params = loaded;
}
}  // namespace

void saveSegmentationParams(const SegmentationParams& params, mrpt::config::CConfigFileBase& cfg,
                            const std::string& section) {
  SegmentationParams copy = params;
  forEachKey(copy, [&](const char* key, auto& field) {
    std::ostringstream os;
    os << std::setprecision(std::numeric_limits<double>::max_digits10) << field;
    cfg.write(section, key, os.str());
  });
}

SegmentationParams loadSegmentationParamsFile(const std::string& path, const std::string& section) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot open configuration file '" + path + "'");
  std::stringstream text;
  text << in.rdbuf();
  mrpt::config::CConfigFileMemory cfg;
  const bool yaml = endsWith(path, ".yaml") || endsWith(path, ".yml");
  if (yaml) {
    try {
      cfg.setContentFromYAML(text.str());
    } catch (const std::exception& e) {
      throw std::invalid_argument(path + ": not valid YAML: " + e.what());
    }
  } else {
    cfg.setContent(text.str());
  }
  SegmentationParams params;
  loadImpl(params, cfg, section, path, keyLines(text.str(), section, yaml));
  return params;
}

}  // namespace lidarseg::mrpt_adapter
