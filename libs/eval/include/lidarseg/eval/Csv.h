#pragma once
/// @file Csv.h
/// The one splitter of the project's comma-separated texts: CSV files (feature truth,
/// region tables, batch metrics) and command-line lists ("icp,icp-s2s", "1-10,12").

#include <string>
#include <vector>

namespace lidarseg::eval {

/// The fields of one line, split at commas. No quoting (the project's files never quote);
/// each field is trimmed of spaces, tabs and a carriage return; a trailing comma gives an
/// empty last field; an empty line gives no field.
std::vector<std::string> splitCsvLine(const std::string& line);

}  // namespace lidarseg::eval
