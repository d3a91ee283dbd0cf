#include "ConfigKeys.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iomanip>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace lidarseg::mrpt_adapter::detail {

namespace {
std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r\n");
  if (b == std::string::npos) return {};
  const auto e = s.find_last_not_of(" \t\r\n");
  return s.substr(b, e - b + 1);
}

bool endsWith(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() &&
         std::equal(suffix.rbegin(), suffix.rend(), s.rbegin(),
                    [](char a, char b) { return std::tolower(a) == std::tolower(b); });
}
}  // namespace

LoadedConfig readConfigFile(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot open configuration file '" + path + "'");
  std::stringstream text;
  text << in.rdbuf();
  LoadedConfig out;
  out.text = text.str();
  out.yaml = endsWith(path, ".yaml") || endsWith(path, ".yml");
  if (out.yaml) {
    try {
      out.cfg.setContentFromYAML(out.text);
    } catch (const std::exception& e) {
      throw std::invalid_argument(path + ": not valid YAML: " + e.what());
    }
  } else {
    out.cfg.setContent(out.text);
  }
  return out;
}

LineMap keyLines(const std::string& text, const std::string& section, bool yaml) {
  LineMap lines;
  std::istringstream in(text);
  std::string line;
  std::string current;
  for (int number = 1; std::getline(in, line); ++number) {
    const std::string t = trim(line);
    if (t.empty() || t[0] == '#' || t[0] == ';' || t.rfind("//", 0) == 0) continue;
    const bool indented = !line.empty() && (line[0] == ' ' || line[0] == '\t');
    if (!yaml && t[0] == '[') {
      current = t.substr(1, t.find(']') - 1);
      continue;
    }
    const auto sep = t.find(yaml ? ':' : '=');
    if (sep == std::string::npos) continue;
    const std::string key = trim(t.substr(0, sep));
    if (yaml && !indented) {
      current = key;
      continue;
    }
    if (current == section && !lines.count(key)) lines[key] = number;
  }
  return lines;
}

std::string where(const std::string& source, const LineMap& lines, const std::string& section,
                  const std::string& key) {
  const auto it = lines.find(key);
  const std::string at = it == lines.end() ? source : source + ":" + std::to_string(it->second);
  return at + " [" + section + "] " + key;
}

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

void rejectUnknownKeys(const mrpt::config::CConfigFileBase& cfg, const std::string& section,
                       const std::vector<std::string>& known, const std::string& source,
                       const LineMap& lines) {
  std::vector<std::string> present;
  cfg.getAllKeys(section, present);
  for (const std::string& key : present) {
    if (std::find(known.begin(), known.end(), key) == known.end()) {
      throw std::invalid_argument(where(source, lines, section, key) + ": unknown key");
    }
  }
}

void rethrowWithLocation(const std::invalid_argument& e, const std::string& source,
                         const LineMap& lines, const std::string& section) {
  const std::string message = e.what();
  const std::string key = message.substr(0, message.find(' '));
  throw std::invalid_argument(where(source, lines, section, key) + ": " + message);
}

std::string formatValue(double v) {
  std::ostringstream os;
  os << std::setprecision(std::numeric_limits<double>::max_digits10) << v;
  return os.str();
}

}  // namespace lidarseg::mrpt_adapter::detail
