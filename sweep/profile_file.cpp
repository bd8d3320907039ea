// Reading a profile file: CSV with a header of "name [unit]" cells, or HDF5 1-D datasets with a
// "units" attribute (sweep/profile.hpp).
#include <hdf5.h>

#include <charconv>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <sstream>

#include "sweep/profile.hpp"
#include "sweep/study.hpp"

namespace rodend {
namespace fs = std::filesystem;
namespace {

/// The shortest text that reads back as x.
std::string format(double x) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, x);
  return std::string(buf, r.ptr);
}

[[noreturn]] void refuse(const ProfileRequest& r, const std::string& where,
                         const std::string& problem) {
  throw InputError("", r.file + (where.empty() ? "" : " " + where) + ": " + problem);
}

/// A unit as written, with its product signs made alike ("N m", "N.m", "N·m" -> "N*m").
std::string normal_unit(std::string u) {
  std::string out;
  for (std::size_t i = 0; i < u.size(); ++i) {
    if (u.compare(i, 2, "\xc2\xb7") == 0) {  // U+00B7 middle dot
      out += '*';
      ++i;
    } else if (u[i] == ' ' || u[i] == '.') {
      out += '*';
    } else {
      out += u[i];
    }
  }
  return out;
}

void check_unit(const ProfileRequest& r, const std::string& where, const std::string& column,
                const std::string& unit, const std::string& expected) {
  if (unit.empty())
    refuse(r, where,
           "column '" + column + "' states no unit; expected '" + expected +
               "' (a CSV header cell '" + column + " [" + expected +
               "]', an HDF5 'units' attribute)");
  if (normal_unit(unit) != normal_unit(expected))
    refuse(r, where,
           "column '" + column + "' is in '" + unit + "'; expected '" + expected +
               "' (SI, as the parameter it drives)");
}

/// The samples read, checked: finite, time strictly increasing, at least two.
void check_samples(const ProfileRequest& r, const ProfileData& d,
                   const std::vector<std::string>& where) {
  for (std::size_t i = 0; i < d.time.size(); ++i) {
    if (!std::isfinite(d.time[i]) || !std::isfinite(d.value[i]))
      refuse(r, where[i],
             "column '" + (std::isfinite(d.time[i]) ? r.column : r.time_column) + "' holds " +
                 format(std::isfinite(d.time[i]) ? d.value[i] : d.time[i]) +
                 "; expected finite numbers (no NaN or infinity)");
    if (i > 0 && !(d.time[i] > d.time[i - 1]))
      refuse(r, where[i],
             "time " + format(d.time[i]) + " s does not come after the previous sample's " +
                 format(d.time[i - 1]) + " s; expected a strictly increasing time column " +
                 "(no repeated or decreasing times)");
  }
  if (d.time.size() < 2)
    refuse(r, "", "holds " + std::to_string(d.time.size()) + " sample(s); expected at least two");
}

std::string trim(const std::string& s) {
  const auto a = s.find_first_not_of(" \t\r");
  if (a == std::string::npos) return "";
  return s.substr(a, s.find_last_not_of(" \t\r") - a + 1);
}

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> cells;
  std::string cell;
  std::istringstream in(line);
  while (std::getline(in, cell, ',')) cells.push_back(trim(cell));
  if (!line.empty() && line.back() == ',') cells.emplace_back();
  return cells;
}

/// A header cell "name [unit]" -> {name, unit} (unit empty when the cell has none).
std::pair<std::string, std::string> header_cell(const std::string& cell) {
  const auto open = cell.rfind('[');
  if (open == std::string::npos || cell.back() != ']') return {cell, ""};
  return {trim(cell.substr(0, open)), trim(cell.substr(open + 1, cell.size() - open - 2))};
}

/// The position of column `name` in the header, checking its unit.
std::size_t find_column(const ProfileRequest& r, const std::string& where,
                        const std::vector<std::string>& header, const std::string& name,
                        const std::string& unit) {
  std::string names;
  for (std::size_t i = 0; i < header.size(); ++i) {
    const auto [n, u] = header_cell(header[i]);
    if (n == name) {
      check_unit(r, where, name, u, unit);
      return i;
    }
    names += (names.empty() ? "'" : ", '") + n + "'";
  }
  refuse(r, where, "has no column '" + name + "'; its header names " + names);
}

double parse_cell(const ProfileRequest& r, const std::string& where, const std::string& column,
                  const std::string& cell) {
  char* end = nullptr;
  const double x = std::strtod(cell.c_str(), &end);
  if (cell.empty() || end != cell.c_str() + cell.size())
    refuse(r, where, "column '" + column + "' holds '" + cell + "'; expected a number");
  return x;
}

ProfileData read_csv(const ProfileRequest& r, const std::string& text) {
  ProfileData d;
  std::vector<std::string> where, header;
  std::size_t t_col = 0, v_col = 0;
  std::istringstream in(text);
  std::string line;
  for (long n = 1; std::getline(in, line); ++n) {
    line = trim(line);
    if (line.empty() || line[0] == '#') continue;  // blank lines and comments (provenance)
    const std::string at = "line " + std::to_string(n);
    const std::vector<std::string> cells = split(line);
    if (header.empty()) {
      header = cells;
      t_col = find_column(r, at + " (the header)", header, r.time_column, "s");
      v_col = find_column(r, at + " (the header)", header, r.column, r.unit);
      continue;
    }
    if (cells.size() != header.size())
      refuse(r, at,
             std::to_string(cells.size()) + " fields; expected " + std::to_string(header.size()) +
                 ", as the header has");
    d.time.push_back(parse_cell(r, at, r.time_column, cells[t_col]));
    d.value.push_back(parse_cell(r, at, r.column, cells[v_col]));
    where.push_back(at);
  }
  if (header.empty())
    refuse(r, "",
           "has no header; expected a first line such as 'time [s]," + r.column + " [" + r.unit +
               "]'");
  check_samples(r, d, where);
  return d;
}

/// An HDF5 identifier closed when it goes out of scope.
struct H5Handle {
  hid_t id = -1;
  herr_t (*close)(hid_t) = nullptr;
  ~H5Handle() {
    if (id >= 0 && close) close(id);
  }
};

std::string units_attribute(const ProfileRequest& r, hid_t dataset, const std::string& name) {
  if (H5Aexists(dataset, "units") <= 0) return "";
  H5Handle a{H5Aopen(dataset, "units", H5P_DEFAULT), H5Aclose};
  H5Handle ft{a.id >= 0 ? H5Aget_type(a.id) : -1, H5Tclose};
  if (ft.id < 0 || H5Tget_class(ft.id) != H5T_STRING)
    refuse(r, "dataset '" + name + "'", "its 'units' attribute is not a string");
  if (H5Tis_variable_str(ft.id) > 0) {
    char* raw = nullptr;
    H5Handle mt{H5Tcopy(ft.id), H5Tclose};  // the file's charset (h5py writes UTF-8)
    if (H5Aread(a.id, mt.id, &raw) < 0 || !raw)
      refuse(r, "dataset '" + name + "'", "its 'units' attribute cannot be read");
    std::string u(raw);
    H5free_memory(raw);
    return u;
  }
  std::string u(H5Tget_size(ft.id), '\0');
  if (H5Aread(a.id, ft.id, u.data()) < 0)
    refuse(r, "dataset '" + name + "'", "its 'units' attribute cannot be read");
  return trim(u.substr(0, u.find('\0')));
}

std::vector<double> read_dataset(const ProfileRequest& r, hid_t file, const std::string& name,
                                 const std::string& unit) {
  const std::string where = "dataset '" + name + "'";
  if (H5Lexists(file, name.c_str(), H5P_DEFAULT) <= 0)
    refuse(r, "", "has no dataset '" + name + "'; expected a 1-D dataset with a 'units' attribute");
  H5Handle d{H5Dopen2(file, name.c_str(), H5P_DEFAULT), H5Dclose};
  if (d.id < 0) refuse(r, where, "is not a dataset");
  H5Handle space{H5Dget_space(d.id), H5Sclose};
  hsize_t n = 0;
  if (H5Sget_simple_extent_ndims(space.id) != 1 ||
      H5Sget_simple_extent_dims(space.id, &n, nullptr) != 1)
    refuse(r, where, "is not one-dimensional; expected one value per sample");
  check_unit(r, where, name, units_attribute(r, d.id, name), unit);
  std::vector<double> out(n);
  if (n > 0 && H5Dread(d.id, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data()) < 0)
    refuse(r, where, "cannot be read as numbers");
  return out;
}

ProfileData read_hdf5(const ProfileRequest& r) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);  // the messages below say what failed
  H5Handle f{H5Fopen(r.resolved.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose};
  if (f.id < 0) refuse(r, "", "cannot be opened as an HDF5 file");
  ProfileData d;
  d.time = read_dataset(r, f.id, r.time_column, "s");
  d.value = read_dataset(r, f.id, r.column, r.unit);
  if (d.time.size() != d.value.size())
    refuse(r, "",
           "datasets '" + r.time_column + "' and '" + r.column + "' hold " +
               std::to_string(d.time.size()) + " and " + std::to_string(d.value.size()) +
               " values; expected one value per time");
  std::vector<std::string> where;
  for (std::size_t i = 0; i < d.time.size(); ++i) where.push_back("element " + std::to_string(i));
  check_samples(r, d, where);
  return d;
}

std::string read_bytes(const ProfileRequest& r) {
  std::error_code ec;
  const fs::file_status st = fs::status(r.resolved, ec);
  if (ec || !fs::exists(st))
    refuse(r, "", "cannot open the profile file (" + r.resolved.string() + "): no such file");
  if (!fs::is_regular_file(st)) refuse(r, "", "is not a regular file; expected a CSV or HDF5 file");
  if (fs::file_size(r.resolved, ec) > kMaxProfileBytes)
    refuse(r, "", "is larger than 256 MiB, the limit of a profile file");
  std::ifstream in(r.resolved, std::ios::binary);
  if (!in) refuse(r, "", "cannot be read (" + r.resolved.string() + ")");
  std::string bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  if (in.bad()) refuse(r, "", "cannot be read (" + r.resolved.string() + ")");
  return bytes;
}

}  // namespace

ProfileData read_profile_file(const ProfileRequest& r) {
  const std::string bytes = read_bytes(r);
  static constexpr char kHdf5Signature[] = "\x89HDF\r\n\x1a\n";
  ProfileData d = bytes.compare(0, 8, kHdf5Signature, 8) == 0 ? read_hdf5(r) : read_csv(r, bytes);
  d.file = r.file;
  d.resolved = r.resolved.string();
  d.content_hash = fnv1a64_hex(bytes);
  d.column = r.column;
  d.unit = r.unit;
  compute_pchip_slopes(d);
  return d;
}

}  // namespace rodend
