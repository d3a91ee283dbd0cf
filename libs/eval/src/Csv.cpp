#include "lidarseg/eval/Csv.h"

#include <algorithm>

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

CsvReader::CsvReader(std::istream& in, std::string source, bool comments)
    : in_(in), source_(std::move(source)), comments_(comments) {}

bool CsvReader::next(std::vector<std::string>& fields) {
  while (std::getline(in_, line_)) {
    ++line_number_;
    const auto first = line_.find_first_not_of(" \t\r");
    if (first == std::string::npos) continue;
    if (comments_ && line_[0] == '#') continue;
    fields = splitCsvLine(line_);
    return true;
  }
  return false;
}

std::optional<std::size_t> CsvReader::column(const std::string& name) const {
  const auto it = std::find(header_.begin(), header_.end(), name);
  if (it == header_.end()) return std::nullopt;
  return static_cast<std::size_t>(it - header_.begin());
}

}  // namespace lidarseg::eval
