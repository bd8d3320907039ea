// The cells of one line of a comma-separated file (the profile files of sweep/profile_file.cpp
// and the points files of sweep/design_file.cpp): split at commas, each cell trimmed of blanks
// and a carriage return; a trailing comma is one more, empty, cell.
#pragma once

#include <sstream>
#include <string>
#include <vector>

namespace rodend::csv {

inline std::string trim(const std::string& s) {
  const auto a = s.find_first_not_of(" \t\r");
  if (a == std::string::npos) return "";
  return s.substr(a, s.find_last_not_of(" \t\r") - a + 1);
}

inline std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> cells;
  std::string cell;
  std::istringstream in(line);
  while (std::getline(in, cell, ',')) cells.push_back(trim(cell));
  if (!line.empty() && line.back() == ',') cells.emplace_back();
  return cells;
}

}  // namespace rodend::csv
