#include "lidarseg/vision/RegionTable.h"
#include "lidarseg/eval/Csv.h"

#include <algorithm>
#include <array>
#include <fstream>
#include <optional>
#include <sstream>
#include <stdexcept>

namespace lidarseg::vision {

namespace {

using eval::splitCsvLine;

long parseInteger(const std::string& text, const std::string& where) {
  std::size_t used = 0;
  long v = 0;
  try {
    v = std::stol(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != text.size()) throw std::runtime_error(where + ": '" + text + "' is not a whole number");
  return v;
}

// The box of inclusive corners, or an empty optional when out of range.
std::optional<cv::Rect> boxOf(const long (&v)[4]) {
  for (long c : v) {
    if (c < 0 || c > kMaxRegionPixel) return std::nullopt;
  }
  if (v[2] < v[0] || v[3] < v[1]) return std::nullopt;
  return cv::Rect(static_cast<int>(v[0]), static_cast<int>(v[1]), static_cast<int>(v[2] - v[0] + 1),
                  static_cast<int>(v[3] - v[1] + 1));
}

const std::string kBoxRule = "need 0 <= u_min <= u_max <= " + std::to_string(kMaxRegionPixel) +
                             " and 0 <= v_min <= v_max <= " + std::to_string(kMaxRegionPixel);

}  // namespace

cv::Rect parseRegion(const std::string& text, const std::string& what) {
  const auto cells = splitCsvLine(text);
  if (cells.size() != 4) throw std::invalid_argument(what + " '" + text + "': expected u_min,v_min,u_max,v_max");
  long v[4];
  try {
    for (int k = 0; k < 4; ++k) v[k] = parseInteger(cells[k], what);
  } catch (const std::runtime_error& e) {
    throw std::invalid_argument(e.what());
  }
  const auto box = boxOf(v);
  if (!box) throw std::invalid_argument(what + " '" + text + "': " + kBoxRule);
  return *box;
}

void RegionTable::read(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot read regions file '" + path + "'");
  read(in, path);
}

void RegionTable::read(std::istream& in, const std::string& source) {
  eval::CsvReader reader(in, source);
  std::vector<std::string> cells;
  if (!reader.next(cells)) throw std::runtime_error(source + ": empty (no header)");
  reader.setHeader(cells);
  const std::vector<std::string>& header = reader.header();
  const std::string header_at = reader.where();
  std::array<std::size_t, 4> box{};
  const char* names[4] = {"u_min", "v_min", "u_max", "v_max"};
  for (int k = 0; k < 4; ++k) {
    const auto c = reader.column(names[k]);
    if (!c) throw std::runtime_error(header_at + ": no column '" + names[k] + "' in the header");
    box[k] = *c;
  }
  const auto frame_col = reader.column("frame") ? reader.column("frame") : reader.column("image");
  const auto file_col = reader.column("file");
  if (!frame_col && !file_col) throw std::runtime_error(header_at + ": no column 'frame', 'image' or 'file' in the header");
  while (reader.next(cells)) {
    const std::string at = reader.where();
    if (cells.size() != header.size()) {
      throw std::runtime_error(at + ": " + std::to_string(cells.size()) + " fields, the header has " +
                               std::to_string(header.size()));
    }
    long v[4];
    for (int k = 0; k < 4; ++k) v[k] = parseInteger(cells[box[k]], at + " " + names[k]);
    const auto r = boxOf(v);
    if (!r) throw std::runtime_error(at + ": " + kBoxRule);
    if (file_col && !cells[*file_col].empty()) {
      by_file_[cells[*file_col]].push_back(*r);
    } else if (frame_col) {
      const std::string& f = cells[*frame_col];
      const long index = f == "*" ? -1 : parseInteger(f, at + " " + header[*frame_col]);
      if (index < 0) {
        every_.push_back(*r);
      } else {
        by_index_[static_cast<std::size_t>(index)].push_back(*r);
      }
    } else {
      throw std::runtime_error(at + ": empty 'file' and no frame column");
    }
  }
}

std::vector<cv::Rect> RegionTable::of(std::size_t index, const std::string& file) const {
  std::vector<cv::Rect> out = every_;
  if (const auto it = by_index_.find(index); it != by_index_.end()) out.insert(out.end(), it->second.begin(), it->second.end());
  if (const auto it = by_file_.find(file); it != by_file_.end()) out.insert(out.end(), it->second.begin(), it->second.end());
  return out;
}

std::size_t RegionTable::size() const {
  std::size_t n = every_.size();
  for (const auto& [k, v] : by_index_) n += v.size();
  for (const auto& [k, v] : by_file_) n += v.size();
  return n;
}

}  // namespace lidarseg::vision
