#pragma once
/// @file Csv.h
/// The one splitter of the project's comma-separated texts: CSV files (feature truth,
/// region tables, batch metrics) and command-line lists ("icp,icp-s2s", "1-10,12").

#include <cstddef>
#include <istream>
#include <optional>
#include <string>
#include <vector>

namespace lidarseg::eval {

/// The fields of one line, split at commas. No quoting (the project's files never quote);
/// each field is trimmed of spaces, tabs and a carriage return; a trailing comma gives an
/// empty last field; an empty line gives no field.
std::vector<std::string> splitCsvLine(const std::string& line);

/// The one reader of the project's CSV tables (feature truth, region tables, batch
/// metrics): lines split by splitCsvLine(), numbered from 1 as in an editor, blank lines
/// (and, when asked, lines starting with '#') skipped; the header, when the table has one,
/// names the columns. Reads one line at a time: memory is one line's.
class CsvReader {
 public:
  /// `source` names the table in messages ("FILE:LINE: ..."). `comments`: lines whose
  /// first character is '#' are skipped like blank ones.
  CsvReader(std::istream& in, std::string source, bool comments = false);

  /// The next line that is neither blank nor a comment, split; false at the end.
  bool next(std::vector<std::string>& fields);
  /// Takes `fields` (a line next() gave) as the header: column() then finds names in it.
  void setHeader(std::vector<std::string> fields) { header_ = std::move(fields); }
  const std::vector<std::string>& header() const { return header_; }
  /// The index of the header's column `name`, if it has one.
  std::optional<std::size_t> column(const std::string& name) const;
  /// The number of the line next() gave last (1-based; 0 before the first).
  std::size_t lineNumber() const { return line_number_; }
  /// "SOURCE:LINE", the place of the line next() gave last, for messages.
  std::string where() const { return source_ + ":" + std::to_string(line_number_); }
  const std::string& source() const { return source_; }

 private:
  std::istream& in_;
  std::string source_;
  bool comments_;
  std::size_t line_number_ = 0;
  std::vector<std::string> header_;
  std::string line_;
};

}  // namespace lidarseg::eval
