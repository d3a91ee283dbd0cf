#pragma once
// Private to lidarseg::mrpt: loading and saving a parameter struct through a key table.
//
// A parameter struct is described once by a visitor, `forEachKey(params, visit)`, calling
// visit(key, field) for every field (double, std::size_t, std::uint64_t or bool). From it come load (strict
// number parsing, unknown-key check, validate(), errors naming file:line [section] key),
// save (full precision) and the list of keys.

#include <array>
#include <cctype>
#include <limits>
#include <map>
#include <string>
#include <type_traits>
#include <vector>

#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/config/CConfigFileMemory.h>

#include "lidarseg/core/Scan.h"
#include "lidarseg/core/Segmentation.h"

namespace lidarseg::mrpt_adapter::detail {

/// The names of an enumeration's values in the configuration files, in value order
/// (specialised for each enum a key table holds).
template <typename E>
struct EnumNames;
template <>
struct EnumNames<CascadeLevel> {
  static constexpr std::array<const char*, 4> names = {"wall_danielsson", "fused", "eroded", "fused_again"};
};
template <>
struct EnumNames<ScanStamp> {
  static constexpr std::array<const char*, 3> names = {"first", "middle", "last"};
};

/// The value named `text` (case and '-' / '_' ignored), or its number (older files).
/// @throws std::invalid_argument naming `context` and the accepted names.
template <typename E>
E parseEnum(const std::string& text, const std::string& context) {
  std::string key;
  for (char c : text) key += c == '-' ? '_' : static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  const auto& names = EnumNames<E>::names;
  for (std::size_t k = 0; k < names.size(); ++k) {
    if (key == names[k]) return static_cast<E>(k);
  }
  std::string list;
  for (const char* n : names) list += std::string(list.empty() ? "" : ", ") + n;
  if (!key.empty() && key.find_first_not_of("0123456789") == std::string::npos && key.size() < 4) {
    const std::size_t v = std::stoul(key);
    if (v < names.size()) return static_cast<E>(v);
  }
  throw std::invalid_argument(context + ": '" + text + "' is not one of " + list);
}

/// Line number (1-based) of each key of one section in the source text.
using LineMap = std::map<std::string, int>;

/// A configuration file read into memory: INI, or YAML when the name ends in .yaml/.yml
/// (top-level keys are sections, as in CConfigFileBase::setContentFromYAML).
struct LoadedConfig {
  mrpt::config::CConfigFileMemory cfg;
  std::string text;
  bool yaml = false;
  /// Line of each key, per section (from the YAML parser's marks; scanned for INI).
  std::map<std::string, LineMap> lines;

  const LineMap& linesOf(const std::string& section) const;
};

/// The largest configuration file read (bytes).
inline constexpr std::size_t kMaxConfigBytes = std::size_t{1} << 20;

/// @throws std::runtime_error if the file cannot be read, is a directory or is larger than
/// kMaxConfigBytes; std::invalid_argument for bad YAML (or YAML nested too deep).
LoadedConfig readConfigFile(const std::string& path);

/// Lines of the keys of `section` in an INI text (section names compared as MRPT does:
/// trimmed, case-insensitive).
LineMap iniKeyLines(const std::string& text, const std::string& section);

/// Throws naming the source when `section` is absent: a misspelt or missing section must
/// not silently give the defaults.
void requireSection(const mrpt::config::CConfigFileBase& cfg, const std::string& section,
                    const std::string& source);

/// "file.ini:12 [section] key" (without ":line" when unknown).
std::string where(const std::string& source, const LineMap& lines, const std::string& section,
                  const std::string& key);

double parseDouble(const std::string& text, const std::string& context);
std::size_t parseCount(const std::string& text, const std::string& context);

/// Throws naming the first key of `section` that `known` does not list.
void rejectUnknownKeys(const mrpt::config::CConfigFileBase& cfg, const std::string& section,
                       const std::vector<std::string>& known, const std::string& source,
                       const LineMap& lines);

/// Rethrows a validate() failure (whose message starts with the key) with its location.
[[noreturn]] void rethrowWithLocation(const std::invalid_argument& e, const std::string& source,
                                      const LineMap& lines, const std::string& section);

template <typename Params, typename ForEachKey>
std::vector<std::string> keysOf(ForEachKey forEachKey) {
  std::vector<std::string> keys;
  Params p;
  forEachKey(p, [&](const char* key, auto&) { keys.emplace_back(key); });
  return keys;
}

/// Reads the keys present in `section` into `params` (absent keys keep their value), then
/// validates; `params` is only changed when everything is valid.
template <typename Params, typename ForEachKey>
void loadKeys(Params& params, const mrpt::config::CConfigFileBase& cfg, const std::string& section,
              const std::string& source, const LineMap& lines, ForEachKey forEachKey) {
  requireSection(cfg, section, source);
  rejectUnknownKeys(cfg, section, keysOf<Params>(forEachKey), source, lines);
  Params loaded = params;
  forEachKey(loaded, [&](const char* key, auto& field) {
    if (!cfg.keyExists(section, key)) return;
    const std::string text = cfg.read_string(section, key, "");
    using Field = std::decay_t<decltype(field)>;
    if constexpr (std::is_same_v<Field, double>) {
      field = parseDouble(text, where(source, lines, section, key));
    } else if constexpr (std::is_same_v<Field, bool>) {
      const std::size_t v = parseCount(text, where(source, lines, section, key));
      if (v > 1) {
        throw std::invalid_argument(where(source, lines, section, key) + ": '" + text +
                                    "' is not 0 or 1");
      }
      field = v == 1;
    } else if constexpr (std::is_enum_v<Field>) {
      field = parseEnum<Field>(text, where(source, lines, section, key));
    } else {
      const std::size_t v = parseCount(text, where(source, lines, section, key));
      if (v > static_cast<std::size_t>(std::numeric_limits<Field>::max())) {
        throw std::invalid_argument(where(source, lines, section, key) + ": '" + text + "' is too large");
      }
      field = static_cast<Field>(v);
    }
  });
  try {
    loaded.validate();
  } catch (const std::invalid_argument& e) {
    rethrowWithLocation(e, source, lines, section);
  }
  params = loaded;
}

/// Writes every key of `params` with full precision.
std::string formatValue(double v);
template <typename Params, typename ForEachKey>
void saveKeys(const Params& params, mrpt::config::CConfigFileBase& cfg, const std::string& section,
              ForEachKey forEachKey) {
  Params copy = params;
  forEachKey(copy, [&](const char* key, auto& field) {
    using Field = std::decay_t<decltype(field)>;
    if constexpr (std::is_enum_v<Field>) {
      cfg.write(section, key, std::string(EnumNames<Field>::names.at(static_cast<std::size_t>(field))));
    } else {
      cfg.write(section, key, formatValue(static_cast<double>(field)));
    }
  });
}

}  // namespace lidarseg::mrpt_adapter::detail
