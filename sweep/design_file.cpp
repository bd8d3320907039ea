// The file design method (sweep/design_methods.def; docs/uncertainty.md): the points of a CSV
// file, a header row of factor key paths, then one row per case. Comment lines (#) and blank
// lines are skipped; a UTF-8 byte-order mark is not part of the first cell.
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>

#include "core/errors.hpp"
#include "sweep/csv_cells.hpp"
#include "sweep/design.hpp"
#include "sweep/study.hpp"

namespace rodend {
namespace {

/// The largest points file read (the case limit of a study, 1e7 rows, at a few numbers each).
constexpr std::uintmax_t kMaxPointsBytes = 256u << 20;

using csv::split;
using csv::trim;

/// At most 40 bytes of a cell, for a message.
std::string excerpt(const std::string& s) {
  return s.size() <= 40 ? s : s.substr(0, 37) + "...";
}

std::string read_bytes(const Design& d) {
  std::error_code ec;
  const std::string path = d.resolved.string();
  if (!std::filesystem::exists(d.resolved, ec))
    throw InputError("design.file", d.file + ": no such file (" + path +
                                        "; a relative path is read from the study file's folder)");
  if (!std::filesystem::is_regular_file(d.resolved, ec))
    throw InputError("design.file", d.file + " (" + path +
                                        ") is not a regular file; expected a "
                                        "CSV file of points");
  if (std::filesystem::file_size(d.resolved, ec) > kMaxPointsBytes)
    throw InputError("design.file", d.file + " is larger than 256 MiB, the limit of a points file");
  std::ifstream in(d.resolved, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  if (!in && !in.eof())
    throw InputError("design.file", d.file + ": cannot be read (" + std::strerror(errno) + ")");
  return text.str();
}

/// The header's cells as the design's factors, each key path checked.
void read_header(Design& d, const std::vector<std::string>& cells, const std::string& at) {
  if (cells.size() > kMaxDesignFactors)
    throw InputError("design.file", d.file + ", " + at + " (the header): more than " +
                                        std::to_string(kMaxDesignFactors) + " columns (factors)");
  for (std::size_t c = 0; c < cells.size(); ++c) {
    const std::string context =
        d.file + ", " + at + " (the header), column " + std::to_string(c + 1) + ": ";
    if (cells[c].empty())
      throw InputError("design.file", context +
                                          "empty; expected a factor's key path such as "
                                          "parameters.contact.clearance");
    check_factor_key(cells[c], "design.file", context, d.factors);
    d.factors.push_back({cells[c], "design.file", {}, "design.file", context});
  }
}

/// One row of points appended to the design's values.
void read_row(Design& d, const std::vector<std::string>& cells, const std::string& at) {
  const std::size_t dims = d.factors.size();
  if (cells.size() != dims)
    throw InputError("design.file", d.file + ", " + at + ": " + std::to_string(cells.size()) +
                                        " fields; expected " + std::to_string(dims) +
                                        ", one per column of the header");
  for (std::size_t c = 0; c < dims; ++c) {
    char* end = nullptr;
    const double x = std::strtod(cells[c].c_str(), &end);
    if (cells[c].empty() || end != cells[c].c_str() + cells[c].size() || !std::isfinite(x))
      throw InputError("design.file", d.file + ", " + at + ", column '" + d.factors[c].key +
                                          "': '" + excerpt(cells[c]) +
                                          "'; expected a finite number");
    d.values.push_back(x);
  }
}

}  // namespace

void read_design_file(Design& d) {
  const std::string bytes = read_bytes(d);
  d.content_fnv1a64 = fnv1a64_hex(bytes);
  static constexpr char kBom[] = "\xef\xbb\xbf";
  std::istringstream in(bytes.compare(0, 3, kBom) == 0 ? bytes.substr(3) : bytes);
  std::string line;
  bool header = true;
  for (long n = 1; std::getline(in, line); ++n) {
    line = trim(line);
    if (line.empty() || line[0] == '#') continue;
    const std::string at = "line " + std::to_string(n);
    if (header)
      read_header(d, split(line), at);
    else
      read_row(d, split(line), at);
    header = false;
  }
  if (header)
    throw InputError("design.file", d.file +
                                        " has no header; expected a first line of factor key "
                                        "paths such as parameters.contact.clearance");
  if (d.values.empty())
    throw InputError("design.file",
                     d.file + " has a header but no row of points; expected one row per case");
  d.size = d.values.size() / d.factors.size();
}

}  // namespace rodend
