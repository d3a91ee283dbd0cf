#include "lidarseg/eval/Csv.h"

namespace lidarseg::eval {

std::vector<std::string> splitCsvLine(const std::string& line) {
  std::vector<std::string> cells;
  if (line.find_first_not_of(" \t\r") == std::string::npos) return cells;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = line.find(',', start);
    const std::string c = line.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    const auto b = c.find_first_not_of(" \t\r"), e = c.find_last_not_of(" \t\r");
    cells.push_back(b == std::string::npos ? std::string() : c.substr(b, e - b + 1));
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return cells;
}

}  // namespace lidarseg::eval
