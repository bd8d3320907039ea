// Tests of case files written from a template (sweep/results/case_template.hpp, issue 33): HDF5
// builds one file per shape of case, every other case of that shape is written without entering
// HDF5, and the files read back exactly as the ones HDF5 builds case by case.
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "fixture.hpp"
#include "sweep/results.hpp"

namespace fs = std::filesystem;
using rodend::test::TempDir;
using namespace rodend;

namespace {

CaseSpec template_spec(long index) {
  CaseSpec spec;
  spec.index = index;
  spec.scene = "gravity-drop";
  spec.parameters = ParameterSet::defaults_for("gravity-drop");
  // a value of every length: the parameters_json and case_json strings change size
  spec.parameters.set("contact.clearance", 1e-4 * (1.0 + 1.0 / static_cast<double>(index + 3)));
  spec.coordinates =
      Json{{"parameters.contact.clearance", spec.parameters.number("contact.clearance")}};
  spec.signals = {SignalId::time, SignalId::ball_position};
  spec.id = "tmpl" + std::to_string(1000000000000 + index);
  return spec;
}

/// 9001 samples: two whole chunks of 4096 rows and an edge chunk; values differ per case.
History template_history(long index) {
  History h;
  h.samples = 9001;
  h.signals = {SignalId::time, SignalId::ball_position};
  h.values.resize(2);
  for (long long i = 0; i < h.samples; ++i) {
    h.values[0].push_back(1e-4 * static_cast<double>(i));
    for (int k = 0; k < 3; ++k)
      h.values[1].push_back(std::sin(1e-3 * static_cast<double>(i * (k + 1) + index)));
  }
  // a 2-D array with a coordinate and a dimension without a variable, as the wear maps have
  CaseArray lat{"maps",      "latitude", "rad", "cell centres", {3}, {0.1, 0.2, 0.3 + index},
                {"latitude"}};
  CaseArray depth{"maps", "depth", "m", "depth of wear", {3, 4}, {}, {"latitude", "sector"}};
  for (int i = 0; i < 12; ++i)
    depth.values.push_back(1e-9 * (i + 1) * static_cast<double>(index + 1));
  h.arrays = {lat, depth};
  return h;
}

/// Strings of sizes 0 to ~10 kB (beyond one 4 kB heap collection), with UTF-8.
CaseRecord template_record(const CaseSpec& spec) {
  CaseRecord r;
  r.id = spec.id;
  r.index = spec.index;
  r.scene = spec.scene;
  r.coordinates = spec.coordinates;
  r.status = spec.index % 2 == 0 ? RunStatus::ok : RunStatus::penetration_limit;
  for (long i = 0; i < spec.index * spec.index * 40; ++i) r.message += i % 7 == 0 ? "µ" : "m";
  r.t_reached = 0.25 + static_cast<double>(spec.index);
  r.wall_time = 1.0 / static_cast<double>(spec.index + 1);
  r.steps_accepted = 12345678901LL + spec.index;
  r.steps_rejected = -spec.index;
  r.rhs_calls = 98765 * spec.index;
  r.started_utc = "2024-05-01T10:00:0" + std::to_string(spec.index % 10) + "Z";
  r.finished_utc =
      r.started_utc + " (" + std::string(static_cast<std::size_t>(spec.index), '+') + ")";
  for (std::size_t i = 0; i < r.metrics.size(); ++i)
    r.metrics[i] = (i + static_cast<std::size_t>(spec.index)) % 3 == 2
                       ? std::numeric_limits<double>::quiet_NaN()
                       : 0.125 * static_cast<double>(i) - static_cast<double>(spec.index);
  return r;
}

/// h5dump of the whole file (attributes, data, dimension lists), object addresses left out
/// (they follow the sizes of the strings that come before), or "" when h5dump fails.
std::string dump(const fs::path& file, const fs::path& tmp) {
  const fs::path out = tmp / (file.filename().string() + ".dump");
  const std::string command = "h5dump '" + file.string() + "' > '" + out.string() + "' 2>&1";
  if (std::system(command.c_str()) != 0) return {};
  std::ifstream in(out);
  std::stringstream text;
  text << in.rdbuf();
  std::string body = text.str();
  body.erase(0, body.find('\n'));  // the first line names the file
  return std::regex_replace(body, std::regex("DATASET [0-9]+ "), "DATASET ");
}

/// Runs `write` with RODEND_CASE_TEMPLATES=0 (HDF5 builds the file), then restores it.
template <class Write>
void without_templates(Write&& write) {
  ::setenv("RODEND_CASE_TEMPLATES", "0", 1);
  try {
    write();
  } catch (...) {
    ::unsetenv("RODEND_CASE_TEMPLATES");
    throw;
  }
  ::unsetenv("RODEND_CASE_TEMPLATES");
}

}  // namespace

TEST_CASE("case files of one shape enter HDF5 once whatever their values", "[results][template]") {
  TempDir tmp("template");
  const long long before = hdf5_lock_count();
  constexpr long kCases = 16;
  for (long k = 0; k < kCases; ++k) {
    const CaseSpec spec = template_spec(k);
    write_case_file(tmp.path() / (spec.id + ".h5"), spec, template_record(spec),
                    template_history(k), Json{{"host", std::string(k, 'h')}});
  }
  // the first case builds the template (one entry into HDF5); before issue 33 every case did
  CHECK(hdf5_lock_count() - before <= 1);
  for (long k = 0; k < kCases; ++k) {
    INFO("case " << k);
    const CaseSpec spec = template_spec(k);
    const fs::path file = tmp.path() / (spec.id + ".h5");
    CHECK(verify_case_file(file));
    const auto back = read_case_record(file);
    REQUIRE(back.has_value());
    const CaseRecord want = template_record(spec);
    CHECK(back->id == want.id);
    CHECK(back->message == want.message);
    CHECK(back->finished_utc == want.finished_utc);
    CHECK(back->steps_rejected == want.steps_rejected);
    CHECK(back->wall_time == want.wall_time);
    for (std::size_t i = 0; i < want.metrics.size(); ++i)
      CHECK((std::isnan(want.metrics[i]) ? std::isnan(back->metrics[i])
                                         : back->metrics[i] == want.metrics[i]));
    const History h = template_history(k);
    CHECK(read_signal(file, "time").values == h.values[0]);
    CHECK(read_signal(file, "ball_position").values == h.values[1]);
  }
}

TEST_CASE("a case file from its template dumps as the file HDF5 builds", "[results][template]") {
  TempDir tmp("template");
  for (const long k : {0L, 5L, 16L}) {  // message of 0, 1,000 and 10,240 characters
    INFO("case " << k);
    const CaseSpec spec = template_spec(k);
    const fs::path patched = tmp.path() / ("patched" + std::to_string(k) + ".h5");
    const fs::path built = tmp.path() / ("built" + std::to_string(k) + ".h5");
    const Json prov{{"host", "a host"}, {"study_file", "studies/µ.json"}};
    write_case_file(patched, spec, template_record(spec), template_history(k), prov);
    without_templates(
        [&] { write_case_file(built, spec, template_record(spec), template_history(k), prov); });
    const std::string a = dump(patched, tmp.path()), b = dump(built, tmp.path());
    REQUIRE_FALSE(a.empty());
    CHECK(a.find(spec.id) != std::string::npos);
    CHECK(a.find("@rodend-slot") == std::string::npos);  // no placeholder left
    CHECK(a == b);
  }
}
