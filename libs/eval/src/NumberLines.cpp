#include "NumberLines.h"
#include "lidarseg/core/NumberText.h"
#include "lidarseg/core/ScanRecord.h"

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace lidarseg::eval::detail {

void forEachLineOf8Numbers(const std::string& path, const std::string& kind, const std::string& format,
                           std::size_t stamps,
                           const std::function<void(std::size_t, const std::array<double, 8>&)>& visit) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot open " + kind + " '" + path + "'");
  std::string line;
  std::size_t line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    // An editor's UTF-8 byte-order mark is no part of the first line.
    if (line_no == 1 && line.compare(0, 3, "\xEF\xBB\xBF") == 0) line.erase(0, 3);
    const auto first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;
    const std::string where = path + ":" + std::to_string(line_no) + ": ";
    std::istringstream fields(line);
    std::array<double, 8> v{};
    std::size_t count = 0;
    std::string token;
    while (fields >> token) {
      if (count == v.size()) throw std::runtime_error(where + "more than 8 fields (expected '" + format + "')");
      const ParsedNumber parsed = parseNumber(token);
      v[count] = parsed.value;
      if (parsed.status == ParsedNumber::Status::not_a_number || !std::isfinite(v[count])) {
        throw std::runtime_error(where + "field " + std::to_string(count + 1) + " '" + token +
                                 "' is not a finite number");
      }
      // Poses, motions and quaternions past the logs' own bound (kMaxLogCoordinate): no
      // building's, and their squares overflow every error and deviation to inf.
      if (count >= stamps && std::abs(v[count]) > kMaxLogCoordinate) {
        throw std::runtime_error(where + "field " + std::to_string(count + 1) + " '" + token +
                                 "' is beyond +-1e6 (m, rad): not a pose of a building");
      }
      ++count;
    }
    if (count != v.size()) {
      throw std::runtime_error(where + std::to_string(count) + " fields (expected 8: '" + format + "')");
    }
    visit(line_no, v);
  }
}

}  // namespace lidarseg::eval::detail
