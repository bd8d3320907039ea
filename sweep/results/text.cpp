// The text forms of the results: numbers (shortest_decimal), times (utc_now), the provenance.
#include <charconv>
#include <cmath>
#include <ctime>
#include <string>

#include "rodend_revision.hpp"  // RODEND_VERSION, RODEND_GIT_REVISION (sweep/CMakeLists.txt)
#include "sweep/results.hpp"
#include "sweep/results_dir.hpp"

namespace rodend {

std::string shortest_decimal(double v) {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  char buf[40];
  // the shortest digits that read back exactly, as d.ddde±XX
  const auto r = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::scientific);
  const std::string sci(buf, r.ptr);
  const auto e = sci.find('e');
  const int exp = std::stoi(sci.substr(e + 1));
  if (exp < -4 || exp >= 16) return sci;  // 1e-17, 1.5e+20
  const bool negative = sci[0] == '-';
  std::string digits;
  for (std::size_t i = negative ? 1 : 0; i < e; ++i)
    if (sci[i] != '.') digits += sci[i];
  std::string out = negative ? "-" : "";
  if (exp < 0) {
    out += "0." + std::string(static_cast<std::size_t>(-exp - 1), '0') + digits;  // 0.0005
  } else {
    const auto whole = static_cast<std::size_t>(exp + 1);
    if (digits.size() <= whole)
      out += digits + std::string(whole - digits.size(), '0');  // 12345678901
    else
      out += digits.substr(0, whole) + "." + digits.substr(whole);  // 1.25
  }
  return out;
}

std::string utc_now() {
  const std::time_t now = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&now, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buf;
}

Json provenance(const Study& study) {
  Json p{{"rodend_version", RODEND_VERSION},
         {"git_revision", RODEND_GIT_REVISION},
         {"host", host_name()},
         {"study_file", study.file.string()},
         {"study_name", study.name},
         {"created_utc", utc_now()}};
  if (!study.overrides.empty()) p["overrides"] = study.overrides;  // rodend run --set
  return p;
}

}  // namespace rodend
