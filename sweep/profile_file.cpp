// Reading a profile file: CSV with a header of "name [unit]" cells, or HDF5 1-D datasets with a
// "units" attribute (sweep/profile.hpp).
#include <fcntl.h>
#include <hdf5.h>
#include <linux/magic.h>
#include <sys/stat.h>
#include <sys/vfs.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <sstream>

#include "sweep/csv_cells.hpp"
#include "sweep/profile.hpp"
#include "sweep/study.hpp"

namespace rodend {
namespace {

/// The shortest text that reads back as x.
std::string format(double x) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, x);
  return std::string(buf, r.ptr);
}

/// The length of the valid UTF-8 sequence at s[i] that is not a control character (C1,
/// U+0080-U+009F), or 0.
std::size_t utf8_printable(const std::string& s, std::size_t i) {
  const auto b = [&](std::size_t k) { return static_cast<unsigned char>(s[k]); };
  const unsigned char c = b(i);
  const std::size_t n = c >= 0xf0 && c <= 0xf4 ? 4 : c >= 0xe0 ? 3 : c >= 0xc2 && c < 0xe0 ? 2 : 0;
  if (n == 0 || c > 0xf4 || i + n > s.size()) return 0;
  for (std::size_t k = 1; k < n; ++k)
    if ((b(i + k) & 0xc0) != 0x80) return 0;
  if (c == 0xc2 && b(i + 1) < 0xa0) return 0;                                      // C1 controls
  if ((c == 0xe0 && b(i + 1) < 0xa0) || (c == 0xf0 && b(i + 1) < 0x90)) return 0;  // overlong
  if ((c == 0xed && b(i + 1) >= 0xa0) || (c == 0xf4 && b(i + 1) >= 0x90)) return 0;
  return n;
}

/// `s` as a terminal may show it: control characters and bytes that are not UTF-8 as \xNN (a
/// binary file's bytes, echoed in a message, must not drive the user's terminal).
std::string printable(const std::string& s) {
  std::string out;
  for (std::size_t i = 0; i < s.size();) {
    const auto c = static_cast<unsigned char>(s[i]);
    if (c >= 0x20 && c < 0x7f) {
      out += s[i++];
    } else if (const std::size_t n = c >= 0x80 ? utf8_printable(s, i) : 0; n > 0) {
      out.append(s, i, n);
      i += n;
    } else {
      char hex[8];
      std::snprintf(hex, sizeof hex, "\\x%02x", c);
      out += hex;
      ++i;
    }
  }
  return out;
}

/// A piece of the file quoted in a message: at most 40 bytes of it.
std::string excerpt(const std::string& s) {
  return s.size() <= 40 ? s : s.substr(0, 40) + "...";
}

[[noreturn]] void refuse(const ProfileRequest& r, const std::string& where,
                         const std::string& problem) {
  throw InputError("", printable(r.file + (where.empty() ? "" : " " + where) + ": " + problem));
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

using csv::split;
using csv::trim;

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
    if (i < 20) names += (names.empty() ? "'" : ", '") + excerpt(n) + "'";
  }
  if (header.size() > 20) names += " and " + std::to_string(header.size() - 20) + " more";
  refuse(r, where, "has no column '" + name + "'; its header names " + names);
}

double parse_cell(const ProfileRequest& r, const std::string& where, const std::string& column,
                  const std::string& cell) {
  char* end = nullptr;
  const double x = std::strtod(cell.c_str(), &end);
  if (cell.empty() || end != cell.c_str() + cell.size())
    refuse(r, where, "column '" + column + "' holds '" + excerpt(cell) + "'; expected a number");
  return x;
}

ProfileData read_csv(const ProfileRequest& r, const std::string& text) {
  ProfileData d;
  std::vector<std::string> where, header;
  std::size_t t_col = 0, v_col = 0;
  // a UTF-8 byte-order mark (spreadsheets write one) is not part of the first cell
  static constexpr char kBom[] = "\xef\xbb\xbf";
  std::istringstream in(text.compare(0, 3, kBom) == 0 ? text.substr(3) : text);
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
  // one string of a unit's length: a declared size or count is not trusted before reading
  H5Handle space{H5Aget_space(a.id), H5Sclose};
  if (space.id < 0 || H5Sget_simple_extent_npoints(space.id) != 1 || H5Tget_size(ft.id) > 256)
    refuse(r, "dataset '" + name + "'",
           "its 'units' attribute is not one string of at most 256 bytes; expected a unit such "
           "as 's'");
  std::string u(H5Tget_size(ft.id), '\0');
  if (H5Aread(a.id, ft.id, u.data()) < 0)
    refuse(r, "dataset '" + name + "'", "its 'units' attribute cannot be read");
  return trim(u.substr(0, u.find('\0')));
}

constexpr const char* kHereOnly =
    "; rodend reads a profile's data from the profile file alone, whose content identifies the "
    "cases: copy the data into it";

/// `name` as a link: an external link (to another file) is refused, naming its target.
void check_link(const ProfileRequest& r, hid_t file, const std::string& name) {
  const std::string where = "dataset '" + name + "'";
  H5L_info_t info{};
  if (H5Lget_info(file, name.c_str(), &info, H5P_DEFAULT) < 0)
    refuse(r, where, "cannot be looked up");
  if (info.type == H5L_TYPE_HARD || info.type == H5L_TYPE_SOFT) return;
  std::string target = "another file";
  std::vector<char> val(info.u.val_size + 1, '\0');
  const char *ext_file = nullptr, *ext_path = nullptr;
  unsigned flags = 0;
  if (info.type == H5L_TYPE_EXTERNAL && info.u.val_size < 65536 &&
      H5Lget_val(file, name.c_str(), val.data(), val.size(), H5P_DEFAULT) >= 0 &&
      H5Lunpack_elink_val(val.data(), info.u.val_size, &flags, &ext_file, &ext_path) >= 0)
    target = "'" + std::string(ext_file) + "', dataset '" + ext_path + "'";
  refuse(r, where, "is an external link (to " + target + ")" + kHereOnly);
}

/// A dataset whose data is in this file: not reached through an external link on its path,
/// not virtual, no raw data in external files; its declared size (and chunks') within the
/// limit of a profile file, checked before anything is read or allocated.
void check_dataset(const ProfileRequest& r, hid_t file, hid_t dataset, const std::string& name,
                   hsize_t n) {
  const std::string where = "dataset '" + name + "'";
  H5O_info_t here{}, there{};
  if (H5Oget_info2(file, &here, H5O_INFO_BASIC) < 0 ||
      H5Oget_info2(dataset, &there, H5O_INFO_BASIC) < 0)
    refuse(r, where, "cannot be inspected");
  if (here.fileno != there.fileno)
    refuse(r, where,
           std::string("is stored in another file (an external link on its path)") + kHereOnly);
  H5Handle dcpl{H5Dget_create_plist(dataset), H5Pclose};
  H5Handle type{H5Dget_type(dataset), H5Tclose};
  if (dcpl.id < 0 || type.id < 0) refuse(r, where, "cannot be inspected");
  const H5D_layout_t layout = H5Pget_layout(dcpl.id);
  if (layout == H5D_VIRTUAL)
    refuse(r, where,
           std::string("is a virtual dataset (its data mapped from other datasets)") + kHereOnly);
  if (H5Pget_external_count(dcpl.id) > 0)
    refuse(r, where, std::string("keeps its data in external raw files") + kHereOnly);
  if (H5Tget_class(type.id) != H5T_FLOAT && H5Tget_class(type.id) != H5T_INTEGER)
    refuse(r, where, "does not hold numbers; expected floating-point or integer values");
  constexpr hsize_t kMaxValues = kMaxProfileBytes / sizeof(double);
  const auto limit = [&](hsize_t values, const char* what) {
    if (values > kMaxValues)
      refuse(r, where,
             "declares " + std::to_string(values) + " values" + what +
                 ", more than a profile file may hold (256 MiB as 8-byte numbers, " +
                 std::to_string(kMaxValues) + " values)");
  };
  limit(n, "");
  hsize_t chunk = 0;
  if (layout == H5D_CHUNKED && H5Pget_chunk(dcpl.id, 1, &chunk) == 1)
    limit(chunk * std::max<hsize_t>(H5Tget_size(type.id) / sizeof(double), 1), " per chunk");
}

std::vector<double> read_dataset(const ProfileRequest& r, hid_t file, const std::string& name,
                                 const std::string& unit) {
  const std::string where = "dataset '" + name + "'";
  if (H5Lexists(file, name.c_str(), H5P_DEFAULT) <= 0)
    refuse(r, "", "has no dataset '" + name + "'; expected a 1-D dataset with a 'units' attribute");
  check_link(r, file, name);
  H5Handle d{H5Dopen2(file, name.c_str(), H5P_DEFAULT), H5Dclose};
  if (d.id < 0) refuse(r, where, "is not a dataset");
  H5Handle space{H5Dget_space(d.id), H5Sclose};
  hsize_t n = 0;
  if (H5Sget_simple_extent_ndims(space.id) != 1 ||
      H5Sget_simple_extent_dims(space.id, &n, nullptr) != 1)
    refuse(r, where, "is not one-dimensional; expected one value per sample");
  check_dataset(r, file, d.id, name, n);
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

/// The file's bytes, read through one descriptor: a regular file of at most kMaxProfileBytes,
/// not a file of the kernel's /proc or /sys (whose sizes are not their contents'); a read error
/// is refused naming the file.
std::string read_bytes(const ProfileRequest& r) {
  const std::string path = r.resolved.string();
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);
  if (fd < 0)
    refuse(r, "",
           "cannot open the profile file (" + path +
               "): " + (errno == ENOENT ? std::string("no such file") : std::strerror(errno)));
  struct Closer {
    int fd;
    ~Closer() { ::close(fd); }
  } closer{fd};
  struct stat st {};
  struct statfs fs_info {};
  if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode))
    refuse(r, "", "is not a regular file; expected a CSV or HDF5 file");
  if (::fstatfs(fd, &fs_info) == 0 &&
      (fs_info.f_type == PROC_SUPER_MAGIC || fs_info.f_type == SYSFS_MAGIC))
    refuse(r, "",
           "is a file of the kernel (/proc or /sys, " + path +
               "), not data; expected a CSV or HDF5 file");
  if (static_cast<std::uintmax_t>(st.st_size) > kMaxProfileBytes)
    refuse(r, "", "is larger than 256 MiB, the limit of a profile file");
  std::string bytes;
  char buf[65536];
  while (true) {
    const ssize_t got = ::read(fd, buf, sizeof buf);
    if (got < 0 && errno == EINTR) continue;
    if (got < 0) refuse(r, "", "cannot be read (" + path + ": " + std::strerror(errno) + ")");
    if (got == 0) break;
    bytes.append(buf, static_cast<std::size_t>(got));
    if (bytes.size() > kMaxProfileBytes)  // it grew while read
      refuse(r, "", "is larger than 256 MiB, the limit of a profile file");
  }
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
