#include "ConfigKeys.h"
#include "lidarseg/core/NumberText.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <limits>
#include <map>
#include <sstream>
#include <stdexcept>
#include <vector>

#include <mrpt/containers/yaml.h>

#include "lidarseg/mrpt/ExceptionMessage.h"

namespace lidarseg::mrpt_adapter::detail {

namespace {
std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r\n");
  if (b == std::string::npos) return {};
  const auto e = s.find_last_not_of(" \t\r\n");
  return s.substr(b, e - b + 1);
}

char lower(char c) { return static_cast<char>(std::tolower(static_cast<unsigned char>(c))); }

bool equalsIgnoreCase(const std::string& a, const std::string& b) {
  return a.size() == b.size() &&
         std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) { return lower(x) == lower(y); });
}

bool endsWith(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() && equalsIgnoreCase(s.substr(s.size() - suffix.size()), suffix);
}

// Loads a YAML text of sections (maps of scalars) into `out`, with the keys' lines.
void loadYaml(const std::string& path, LoadedConfig& out) {
  mrpt::containers::yaml doc;
  try {
    doc = mrpt::containers::yaml::FromText(out.text);
  } catch (const std::exception& e) {
    // MRPT's text is a banner and a backtrace before its message: the message, in one line.
    std::string message = exceptionMessage(e.what());
    if (message.find("nVal.has_value()") != std::string::npos || message.find("empty scalar") != std::string::npos) {
      // MRPT's internal assertion after libfyaml's error, which libfyaml printed (with the
      // line and column) on stderr.
      message = "a syntax error (the YAML parser's message with its line is on stderr)";
    }
    throw std::invalid_argument(path + ": not valid YAML: " + message);
  }
  if (doc.isNullNode()) return;
  if (!doc.isMap()) throw std::invalid_argument(path + ": the top level must map section names to keys");
  for (const auto& [section_node, body] : doc.asMap()) {
    const std::string section = section_node.as<std::string>();
    const int section_line = section_node.marks.line + 1;
    if (!body.isMap()) {
      throw std::invalid_argument(path + ":" + std::to_string(section_line) + " [" + section +
                                  "]: a section must map keys to values");
    }
    for (const auto& [key_node, value] : body.asMap()) {
      const std::string key = key_node.as<std::string>();
      const int line = key_node.marks.line + 1;
      if (!value.isScalar()) {
        throw std::invalid_argument(path + ":" + std::to_string(line) + " [" + section + "] " + key +
                                    ": the value must be a single number");
      }
      out.cfg.write(section, key, value.as<std::string>());
      out.lines[section][key] = line;
    }
  }
}
}  // namespace

const LineMap& LoadedConfig::linesOf(const std::string& section) const {
  static const LineMap kNone;
  for (const auto& [name, map] : lines) {
    if (equalsIgnoreCase(name, section)) return map;
  }
  return kNone;
}

namespace {
// YAML nested deeper than this (flow brackets or indentation levels) is refused before the
// parser sees it: libfyaml recurses once per level and overflows the stack on 20,000.
constexpr int kMaxYamlDepth = 64;

void checkYamlNesting(const std::string& path, const std::string& text) {
  int depth = 0, line = 1;
  std::size_t column = 0;
  bool at_start = true;
  for (const char c : text) {
    if (c == '\n') {
      ++line;
      column = 0;
      at_start = true;
      continue;
    }
    if (at_start && c == ' ') {
      ++column;
    } else {
      at_start = false;
    }
    if (c == '[' || c == '{') ++depth;
    if (c == ']' || c == '}') --depth;
    if (depth > kMaxYamlDepth || column > 2 * static_cast<std::size_t>(kMaxYamlDepth)) {
      throw std::invalid_argument(path + ":" + std::to_string(line) + ": YAML nested deeper than " +
                                  std::to_string(kMaxYamlDepth) + " levels");
    }
  }
}


// YAML directives ("%YAML 1.2", "%TAG ...") are refused before the parser sees them: a
// parameter file needs none, and libfyaml 0.8 loops forever on some malformed ones
// (a "%" line after a mapping, found by fuzz_config).
void refuseYamlDirectives(const std::string& path, const std::string& text) {
  int line = 1;
  bool at_start = true;
  for (const char c : text) {
    if (at_start && c == '%') {
      throw std::invalid_argument(path + ":" + std::to_string(line) +
                                  ": YAML directives ('%' at the start of a line) are not supported in a "
                                  "parameter file");
    }
    at_start = c == '\n';
    if (c == '\n') ++line;
  }
}

// One YAML document per parameter file: the parser reads the first and ignores the rest, so
// a second document's keys (even invalid ones) would be dropped without a word. A "---"
// after any content, or a "..." document end, is refused with its line.
void refuseSecondYamlDocument(const std::string& path, const std::string& text) {
  std::istringstream in(text);
  std::string line;
  bool content = false;
  for (int number = 1; std::getline(in, line); ++number) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const bool start = line.rfind("---", 0) == 0 && (line.size() == 3 || line[3] == ' ' || line[3] == '\t');
    const bool end = line.rfind("...", 0) == 0 && (line.size() == 3 || line[3] == ' ' || line[3] == '\t');
    if (end || (start && content)) {
      throw std::invalid_argument(path + ":" + std::to_string(number) +
                                  ": a second YAML document (or a document end '...'); a parameter file holds one");
    }
    const auto first = line.find_first_not_of(" \t");
    if (!start && first != std::string::npos && line[first] != '#') content = true;
  }
}
}  // namespace

namespace {
std::string lowerText(std::string s) {
  for (char& c : s) c = lower(c);
  return s;
}

// The text of a YAML line before its comment ('#' at the start or after a blank, outside
// quotes).
std::string withoutYamlComment(const std::string& line) {
  char quote = 0;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quote != 0) {
      if (c == quote) quote = 0;
    } else if (c == '"' || c == '\'') {
      quote = c;
    } else if (c == '#' && (i == 0 || line[i - 1] == ' ' || line[i - 1] == '\t')) {
      return line.substr(0, i);
    }
  }
  return line;
}

// Block-style YAML checked line by line before the parser (issue 16): MRPT's parser keeps
// the last of two equal keys or sections silently, and fails on an alias or an empty
// section with an assertion text ("nVal.has_value()", "Unexpected empty scalar?!").
void checkYamlStructure(const std::string& path, const std::string& text) {
  std::istringstream in(text);
  std::string raw;
  std::map<std::string, int> sections;  // lower-case name -> line
  std::map<std::string, int> keys;      // of the current section
  std::string section;
  int key_indent = -1;
  struct Pending {
    int line = 0, indent = 0;
    std::string section, key;
  } pending;
  const auto at = [&](int line) { return path + ":" + std::to_string(line); };
  const auto failEmpty = [&]() {
    if (pending.key.empty()) return;
    if (pending.section.empty()) {
      throw std::invalid_argument(at(pending.line) + " [" + pending.key +
                                  "]: the section is empty (a section maps keys to values)");
    }
    throw std::invalid_argument(at(pending.line) + " [" + pending.section + "] " + pending.key + ": no value");
  };
  for (int number = 1; std::getline(in, raw); ++number) {
    const std::string content = withoutYamlComment(raw);
    const std::string t = trim(content);
    if (t.empty() || t == "---" || t == "...") continue;
    const int indent = static_cast<int>(content.find_first_not_of(" \t"));
    // YAML indents with spaces only; the parser's own message for a tab names no file.
    if (content.find('\t') < static_cast<std::size_t>(indent)) {
      throw std::invalid_argument(at(number) + ": a tab in the indentation (YAML indents with spaces only)");
    }
    if (!pending.key.empty()) {
      if (indent <= pending.indent) failEmpty();
      pending = Pending{};
    }
    // A key: the text before the first ':' followed by a blank or the end of the line.
    std::size_t colon = std::string::npos;
    char quote = 0;
    for (std::size_t i = 0; i < t.size(); ++i) {
      if (quote != 0) {
        if (t[i] == quote) quote = 0;
      } else if (t[i] == '"' || t[i] == '\'') {
        quote = t[i];
      } else if (t[i] == ':' && (i + 1 == t.size() || t[i + 1] == ' ' || t[i + 1] == '\t')) {
        colon = i;
        break;
      }
    }
    const std::string value = colon == std::string::npos ? t : trim(t.substr(colon + 1));
    const bool reference = (!value.empty() && (value[0] == '&' || value[0] == '*')) ||
                           (!t.empty() && (t[0] == '&' || t[0] == '*'));
    if (reference) {
      throw std::invalid_argument(at(number) +
                                  ": YAML anchors and aliases ('&name', '*name') are not supported in a "
                                  "parameter file");
    }
    if (colon == std::string::npos || t[0] == '-' || t[0] == '{' || t[0] == '[') continue;
    std::string key = trim(t.substr(0, colon));
    if (key.size() >= 2 && (key[0] == '"' || key[0] == '\'') && key.back() == key[0]) {
      key = key.substr(1, key.size() - 2);
    }
    if (indent == 0) {
      const auto [it, added] = sections.emplace(lowerText(key), number);
      if (!added) {
        throw std::invalid_argument(at(number) + ": section '" + key + "' given twice (first at line " +
                                    std::to_string(it->second) + "); the parser would keep only the last");
      }
      section = key;
      keys.clear();
      key_indent = -1;
      if (value.empty()) pending = Pending{number, indent, "", key};
      continue;
    }
    if (section.empty()) continue;
    if (key_indent < 0) key_indent = indent;
    if (indent != key_indent) continue;
    const auto [it, added] = keys.emplace(lowerText(key), number);  // the store ignores case
    if (!added) {
      throw std::invalid_argument(at(number) + " [" + section + "] " + key + ": given twice (first at line " +
                                  std::to_string(it->second) + "); the parser would keep only the last");
    }
    if (value.empty()) pending = Pending{number, indent, section, key};
  }
  failEmpty();
}

// Keys of YAML flow mappings (`{a: 1, b: 2}`, on one line or over several) checked for
// duplicates, compared without case as the store compares them (issue 16): the parser
// keeps the last of two equal keys silently. Runs after checkYamlNesting (bounded depth).
void checkYamlFlowMappings(const std::string& path, const std::string& text) {
  struct Scope {
    bool mapping = false;
    bool expecting_key = true;
    std::string token;                // the key read so far
    std::map<std::string, int> keys;  // lower-case key -> line
    std::string section;              // the block section it is the value of (depth 1)
  };
  std::vector<Scope> scopes;
  std::istringstream in(text);
  std::string raw;
  std::string section;  // the current block section (a key at indent 0)
  const auto at = [&](int line) { return path + ":" + std::to_string(line); };
  for (int number = 1; std::getline(in, raw); ++number) {
    const std::string line = withoutYamlComment(raw);
    if (scopes.empty()) {
      const std::string t = trim(line);
      if (t.empty()) continue;
      if (line[0] != ' ' && line[0] != '\t' && t[0] != '{' && t[0] != '[') {
        section = trim(t.substr(0, t.find(':')));
      }
    }
    char quote = 0;
    char previous = ' ';  // the last character outside quotes and blanks, of the flow text
    for (std::size_t i = 0; i < line.size(); ++i) {
      const char c = line[i];
      Scope* top = scopes.empty() ? nullptr : &scopes.back();
      const bool reading_key = top != nullptr && top->mapping && top->expecting_key;
      if (quote != 0) {
        if (c == quote) quote = 0, previous = c;
        if (reading_key) top->token += c;
        continue;
      }
      const char next = i + 1 < line.size() ? line[i + 1] : ' ';
      // In block context only a '{' or '[' that starts a value opens a flow collection.
      const bool opens = (c == '{' || c == '[') &&
                         (top != nullptr || previous == ' ' || previous == ':' || previous == '-');
      if (opens) {
        Scope scope;
        scope.mapping = c == '{';
        scope.section = scopes.empty() ? section : std::string();
        scopes.push_back(std::move(scope));
      } else if (top != nullptr && (c == '}' || c == ']')) {
        scopes.pop_back();
        if (!scopes.empty() && scopes.back().mapping) scopes.back().expecting_key = false;
      } else if (top != nullptr && c == ',') {
        if (top->mapping) top->expecting_key = true, top->token.clear();
      } else if (reading_key && c == ':' &&
                 (next == ' ' || next == '\t' || next == ',' || next == '}' || next == '{' || next == '[' ||
                  (!top->token.empty() && (previous == '"' || previous == '\'')))) {
        std::string key = trim(top->token);
        if (key.size() >= 2 && (key[0] == '"' || key[0] == '\'') && key.back() == key[0]) {
          key = key.substr(1, key.size() - 2);
        }
        const auto [it, added] = top->keys.emplace(lowerText(key), number);
        if (!added) {
          const std::string where =
              top->section.empty() ? at(number) + ": key '" + key + "'" : at(number) + " [" + top->section + "] " + key;
          throw std::invalid_argument(where + ": given twice in a flow mapping (first at line " +
                                      std::to_string(it->second) + "); the parser would keep only the last");
        }
        top->expecting_key = false;
        top->token.clear();
      } else if (c == '"' || c == '\'') {
        quote = c;
        if (reading_key) top->token += c;
      } else if (reading_key) {
        top->token += c;
      }
      if (c != ' ' && c != '\t') previous = c;
    }
    if (!scopes.empty() && scopes.back().mapping && scopes.back().expecting_key) scopes.back().token += ' ';
  }
}

// INI checked line by line (issue 16): MRPT keeps the last of two equal keys silently and
// ignores keys before the first [section].
void checkIniStructure(const std::string& path, const std::string& text) {
  std::istringstream in(text);
  std::string line;
  std::string section;
  bool in_section = false;
  std::map<std::pair<std::string, std::string>, int> seen;
  for (int number = 1; std::getline(in, line); ++number) {
    const std::string t = trim(line);
    if (t.empty() || t[0] == '#' || t[0] == ';' || t.rfind("//", 0) == 0) continue;
    // MRPT's preprocessor knows '@define NAME VALUE' and skips any other '@' line silently
    // ('@include other.ini' read nothing).
    if (t[0] == '@') {
      if (t.rfind("@define", 0) == 0 && t.size() > 7 && std::isspace(static_cast<unsigned char>(t[7]))) continue;
      throw std::invalid_argument(path + ":" + std::to_string(number) + ": '" + t.substr(0, 80) +
                                  "' is no directive the INI reader knows (only '@define NAME VALUE'); it would be "
                                  "skipped (there is no '@include': give one file)");
    }
    if (t[0] == '[') {
      if (t.find(']') == std::string::npos) {
        throw std::invalid_argument(path + ":" + std::to_string(number) + ": '" + t +
                                    "' opens a section without closing it ('[name]')");
      }
      const std::size_t close = t.find(']');
      section = trim(t.substr(1, close - 1));
      // MRPT drops the keys of a nameless section, and reads '[matcher]x' as [matcher].
      if (section.empty()) {
        throw std::invalid_argument(path + ":" + std::to_string(number) + ": '" + t.substr(0, 80) +
                                    "' names no section (its keys would be dropped)");
      }
      const std::string after = trim(t.substr(close + 1));
      if (!after.empty() && after[0] != ';' && after[0] != '#') {
        throw std::invalid_argument(path + ":" + std::to_string(number) + ": '" + t.substr(0, 80) +
                                    "': text after the section's ']' (only a comment may follow)");
      }
      in_section = true;
      continue;
    }
    const auto sep = t.find('=');
    if (sep == std::string::npos) {
      // MRPT skips such a line silently: a key written 'key value' or 'key: value' (YAML)
      // would leave its default in place without a word.
      throw std::invalid_argument(path + ":" + std::to_string(number) + ": '" + t.substr(0, 80) +
                                  "' is not a 'key = value' line (nor a [section], a comment or blank)");
    }
    const std::string key = trim(t.substr(0, sep));
    if (key.empty()) {
      throw std::invalid_argument(path + ":" + std::to_string(number) + ": '" + t.substr(0, 80) +
                                  "' gives a value to no key (the line would be dropped)");
    }
    if (!in_section) {
      throw std::invalid_argument(path + ":" + std::to_string(number) + ": key '" + key +
                                  "' before any [section] (every key belongs to a section)");
    }
    const auto [it, added] = seen.emplace(std::make_pair(lowerText(section), lowerText(key)), number);
    if (!added) {
      throw std::invalid_argument(path + ":" + std::to_string(number) + " [" + section + "] " + key +
                                  ": given twice (first at line " + std::to_string(it->second) +
                                  "); only one value may be given");
    }
  }
}
}  // namespace

LoadedConfig readConfigFile(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) {
    throw std::runtime_error("configuration file '" + path + "' is a directory");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot open configuration file '" + path + "'");
  // Read at most the cap and one byte more: /dev/zero or a huge file is refused, not slurped.
  std::string text(kMaxConfigBytes + 1, '\0');
  in.read(text.data(), static_cast<std::streamsize>(text.size()));
  text.resize(static_cast<std::size_t>(in.gcount()));
  if (text.size() > kMaxConfigBytes) {
    throw std::runtime_error("configuration file '" + path + "' is larger than " +
                             std::to_string(kMaxConfigBytes >> 10) + " KiB");
  }
  // A UTF-8 byte-order mark (an editor's) is no part of the first line.
  if (text.compare(0, 3, "\xEF\xBB\xBF") == 0) text.erase(0, 3);
  LoadedConfig out;
  out.text = std::move(text);
  out.yaml = endsWith(path, ".yaml") || endsWith(path, ".yml");
  if (out.yaml) {
    checkYamlNesting(path, out.text);
    refuseYamlDirectives(path, out.text);
    refuseSecondYamlDocument(path, out.text);
    checkYamlStructure(path, out.text);
    checkYamlFlowMappings(path, out.text);
    loadYaml(path, out);
  } else {
    std::vector<std::string> sections;
    try {  // MRPT's INI preprocessor ($env{}, $eval{}, @define) throws on bad syntax
      out.cfg.setContent(out.text);
      out.cfg.getAllSections(sections);
    } catch (const std::exception& e) {
      // MRPT's text is a banner and a backtrace before its message: the message, in one line.
      throw std::invalid_argument(path + ": not a valid INI file: " + exceptionMessage(e.what()));
    }
    checkIniStructure(path, out.text);
    for (const std::string& s : sections) out.lines[s] = iniKeyLines(out.text, s);
  }
  return out;
}

void requireSection(const mrpt::config::CConfigFileBase& cfg, const std::string& section,
                    const std::string& source) {
  if (!cfg.sectionExists(section)) {
    throw std::invalid_argument(source + ": no [" + section + "] section");
  }
}

LineMap iniKeyLines(const std::string& text, const std::string& section) {
  LineMap lines;
  std::istringstream in(text);
  std::string line;
  std::string current;
  for (int number = 1; std::getline(in, line); ++number) {
    const std::string t = trim(line);
    if (t.empty() || t[0] == '#' || t[0] == ';' || t.rfind("//", 0) == 0) continue;
    if (t[0] == '[') {
      current = trim(t.substr(1, t.find(']') - 1));
      continue;
    }
    const auto sep = t.find('=');
    if (sep == std::string::npos) continue;
    // The last occurrence of a key wins in MRPT: point at that one.
    if (equalsIgnoreCase(current, section)) lines[trim(t.substr(0, sep))] = number;
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
  const ParsedNumber parsed = parseNumber(t);
  const double v = parsed.value;
  if (parsed.status == ParsedNumber::Status::not_a_number) {
    throw std::invalid_argument(context + ": '" + text + "' is not a number");
  }
  // A number whose magnitude a double cannot hold at full precision: beyond 1.8e308
  // or below 2.2e-308 (a subnormal, or 0 after underflow).
  if (parsed.status == ParsedNumber::Status::out_of_range || (std::isfinite(v) && v != 0.0 && !std::isnormal(v))) {
    throw std::invalid_argument(context + ": '" + text +
                                "' is out of range (a magnitude from 2.2e-308 to 1.8e308, or 0)");
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
  // The shortest text that reads back as the same double: 0.3, not 0.29999999999999999.
  for (int digits = 6; digits <= std::numeric_limits<double>::max_digits10; ++digits) {
    std::ostringstream os;
    os << std::setprecision(digits) << v;
    if (std::strtod(os.str().c_str(), nullptr) == v) return os.str();
  }
  std::ostringstream os;
  os << std::setprecision(std::numeric_limits<double>::max_digits10) << v;
  return os.str();
}

}  // namespace lidarseg::mrpt_adapter::detail
