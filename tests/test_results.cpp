// Tests of the results files: case file round trip, crash safety (no temporary file left,
// unreadable files read as absent), summary table (CSV header and rows).
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "fixture.hpp"
#include "sweep/results.hpp"
#include "sweep/results/checksum.hpp"

namespace fs = std::filesystem;
using rodend::test::TempDir;
using namespace rodend;

namespace {

std::vector<std::string> entries(const fs::path& dir) {
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

std::vector<std::string> lines_of(const fs::path& file) {
  std::ifstream in(file);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

CaseSpec make_spec(long index, double clearance) {
  CaseSpec spec;
  spec.index = index;
  spec.scene = "gravity-drop";
  spec.parameters = ParameterSet::defaults_for("gravity-drop");
  spec.parameters.set("contact.clearance", clearance);
  spec.coordinates = Json{{"parameters.contact.clearance", clearance}};
  spec.signals = {SignalId::time, SignalId::ball_position};
  spec.id = "00000000000000" + std::to_string(10 + index);
  return spec;
}

History make_history(long long samples) {
  History h;
  h.samples = samples;
  h.signals = {SignalId::time, SignalId::ball_position};
  h.values.resize(2);
  for (long long i = 0; i < samples; ++i) {
    h.values[0].push_back(1e-3 * static_cast<double>(i));
    for (int k = 0; k < 3; ++k) h.values[1].push_back(static_cast<double>(10 * i + k));
  }
  return h;
}

CaseRecord make_record(const CaseSpec& spec) {
  CaseRecord r;
  r.id = spec.id;
  r.index = spec.index;
  r.scene = spec.scene;
  r.coordinates = spec.coordinates;
  r.status = spec.index == 0 ? RunStatus::ok : RunStatus::penetration_limit;
  r.message = spec.index == 0 ? "" : "penetration, \"deep\", at t = 0.01 s";
  r.t_reached = 0.25 + static_cast<double>(spec.index);
  r.wall_time = 1.5;
  r.steps_accepted = 12345678901LL;
  r.steps_rejected = 17;
  r.rhs_calls = 98765;
  r.started_utc = "2024-05-01T10:00:00Z";
  r.finished_utc = "2024-05-01T10:00:02Z";
  r.features = Features{Feature::contact, Feature::wear};
  for (std::size_t i = 0; i < r.metrics.size(); ++i)
    r.metrics[i] = i % 3 == 2 ? std::numeric_limits<double>::quiet_NaN()
                              : 0.125 * static_cast<double>(i) + 1e-17;
  return r;
}

Study make_study(const fs::path& dir) {
  Study study;
  study.file = dir / "clearance.json";
  study.name = "clearance";
  study.scene = "gravity-drop";
  study.output_dir = dir;
  study.axis_keys = {"parameters.contact.clearance"};
  study.cases = {make_spec(0, 5e-4), make_spec(1, 1e-3)};
  study.source =
      Json{{"scene", "gravity-drop"}, {"grid", {{"parameters.contact.clearance", {5e-4, 1e-3}}}}};
  return study;
}

/// write_summary of `rows` (in slot order) into `dir`, through a spool as a run does.
void summarise(const fs::path& dir, const Study& study, const std::vector<CaseRecord>& rows) {
  fs::create_directories(dir);
  RecordSpool spool(dir, rows.size());
  for (std::size_t i = 0; i < rows.size(); ++i) spool.put(i, rows[i]);
  write_summary(dir, study, spool, provenance(study));
}

void require_same_record(const CaseRecord& got, const CaseRecord& want) {
  CHECK(got.id == want.id);
  CHECK(got.index == want.index);
  CHECK(got.scene == want.scene);
  CHECK(got.features == want.features);  // written to the case file and read back (issue 32)
  CHECK(got.coordinates == want.coordinates);
  CHECK(got.status == want.status);
  CHECK(got.message == want.message);
  CHECK(got.t_reached == want.t_reached);
  CHECK(got.wall_time == want.wall_time);
  CHECK(got.steps_accepted == want.steps_accepted);
  CHECK(got.steps_rejected == want.steps_rejected);
  CHECK(got.rhs_calls == want.rhs_calls);
  CHECK(got.started_utc == want.started_utc);
  CHECK(got.finished_utc == want.finished_utc);
  for (std::size_t i = 0; i < want.metrics.size(); ++i) {
    INFO("metric " << metric_catalogue()[i].name);
    if (std::isnan(want.metrics[i]))
      CHECK(std::isnan(got.metrics[i]));
    else
      CHECK(got.metrics[i] == want.metrics[i]);
  }
}

}  // namespace

TEST_CASE("provenance names the version, revision, host and study", "[results]") {
  TempDir tmp;
  const Json p = provenance(make_study(tmp.path()));
  for (const char* key :
       {"rodend_version", "git_revision", "host", "study_file", "study_name", "created_utc"}) {
    INFO(key);
    REQUIRE(p.contains(key));
    CHECK(p[key].is_string());
  }
  CHECK(p["study_name"] == "clearance");
  const std::string t = p["created_utc"];
  REQUIRE(t.size() == 20);
  CHECK(t[4] == '-');
  CHECK(t[10] == 'T');
  CHECK(t.back() == 'Z');
}

TEST_CASE("a case file reads back as the record written", "[results]") {
  TempDir tmp;
  const CaseSpec spec = make_spec(1, 1e-3);
  const CaseRecord record = make_record(spec);
  const fs::path file = tmp.path() / "study" / "cases" / (spec.id + ".h5");  // parents created

  write_case_file(file, spec, record, make_history(5000), provenance(make_study(tmp.path())));

  const auto back = read_case_record(file);
  REQUIRE(back.has_value());
  require_same_record(*back, record);
  // complete file under its final name, no temporary file left beside it
  CHECK(entries(file.parent_path()) == std::vector<std::string>{spec.id + ".h5"});
  // the histories read back value for value (make_history: t = 1e-3 i, position 10 i + k)
  const SignalData t = read_signal(file, "time"), pos = read_signal(file, "ball_position");
  REQUIRE(t.samples == 5000);
  REQUIRE(pos.samples == 5000);
  REQUIRE(pos.width == 3);
  for (std::size_t i : {std::size_t{0}, std::size_t{1}, std::size_t{4095}, std::size_t{4999}}) {
    CHECK(t.at(i) == 1e-3 * static_cast<double>(i));
    for (int k = 0; k < 3; ++k) CHECK(pos.at(i, k) == static_cast<double>(10 * i + k));
  }

  SECTION("rewriting replaces the file") {
    CaseRecord again = record;
    again.status = RunStatus::ok;
    again.message = "";
    write_case_file(file, spec, again, make_history(3), Json::object());
    const auto back2 = read_case_record(file);
    REQUIRE(back2.has_value());
    CHECK(back2->status == RunStatus::ok);
    CHECK(back2->message.empty());
    CHECK(entries(file.parent_path()) == std::vector<std::string>{spec.id + ".h5"});
  }
}

namespace {
/// Replaces the one occurrence of `was` in the bytes of a case file by `now` (same length) and
/// signs the file anew: a file intact but for that change.
void patch_case_file(const fs::path& file, const std::string& was, const std::string& now) {
  std::string bytes;
  {
    std::ifstream in(file, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), {});
  }
  const std::size_t at = bytes.find(was);
  REQUIRE(at != std::string::npos);
  REQUIRE(bytes.find(was, at + 1) == std::string::npos);  // that one place alone
  bytes.replace(at, was.size(), now);
  const auto* image = reinterpret_cast<const unsigned char*>(bytes.data());
  const auto header =
      rodend::results_detail::checksum_header({image + rodend::results_detail::kUserBlock,
                                               bytes.size() - rodend::results_detail::kUserBlock});
  std::copy(header.begin(), header.end(), bytes.begin());
  std::ofstream(file, std::ios::binary | std::ios::trunc) << bytes;
  REQUIRE(verify_case_file(file));
}
}  // namespace

TEST_CASE("a case file whose status is no run status is refused with the names allowed",
          "[results]") {
  // a case file intact but for its status attribute: "penetration_limit" (make_record, case 1)
  // changed to a name no rodend has, its checksum made anew
  TempDir tmp;
  const CaseSpec spec = make_spec(1, 1e-3);
  const fs::path file = tmp.path() / (spec.id + ".h5");
  write_case_file(file, spec, make_record(spec), make_history(3), Json::object());
  patch_case_file(file, "penetration_limit", "penetration_limiz");

  CHECK_FALSE(read_case_record(file).has_value());  // resume: as if absent
  try {
    (void)read_case_record_strict(file);
    FAIL("an unknown status was read back");
  } catch (const std::runtime_error& e) {
    const std::string m = e.what();
    INFO(m);
    CHECK(m.find(file.string()) != std::string::npos);
    CHECK(m.find("attribute status") != std::string::npos);
    CHECK(m.find("\"penetration_limiz\"") != std::string::npos);
    for (const RunStatus s : choice_values<RunStatus>())
      CHECK(m.find("\"" + std::string(to_string(s)) + "\"") != std::string::npos);
  }
}

TEST_CASE("a case file without its status attribute is refused and not read as ok", "[results]") {
  // the attribute's name changed ("status" -> "statuz"; the attribute "status" is the only
  // "status" followed by its terminating NUL in the file), its checksum made anew
  TempDir tmp;
  const CaseSpec spec = make_spec(1, 1e-3);
  const fs::path file = tmp.path() / (spec.id + ".h5");
  write_case_file(file, spec, make_record(spec), make_history(3), Json::object());
  patch_case_file(file, std::string("status\0", 7), std::string("statuz\0", 7));

  CHECK_FALSE(read_case_record(file).has_value());  // resume: as if absent, so it runs again
  try {
    (void)read_case_record_strict(file);
    FAIL("a case file without a status was read back");
  } catch (const std::runtime_error& e) {
    const std::string m = e.what();
    INFO(m);
    CHECK(m.find(file.string()) != std::string::npos);
    CHECK(m.find("attribute status is missing") != std::string::npos);
  }
}

TEST_CASE("a case with no samples still writes its signals", "[results]") {
  TempDir tmp;
  const CaseSpec spec = make_spec(0, 5e-4);
  const CaseRecord record = make_record(spec);
  const fs::path file = tmp.path() / "empty.h5";
  write_case_file(file, spec, record, make_history(0), Json::object());
  const auto back = read_case_record(file);
  REQUIRE(back.has_value());
  require_same_record(*back, record);
  // every recorded signal is there, with no rows, its width and its unit
  CHECK(list_signals(file) == std::vector<std::string>{"ball_position", "time"});
  const SignalData t = read_signal(file, "time");
  CHECK(t.samples == 0);
  CHECK(t.values.empty());
  CHECK(t.width == 1);
  CHECK(t.unit == "s");
  const SignalData p = read_signal(file, "ball_position");
  CHECK(p.samples == 0);
  CHECK(p.values.empty());
  CHECK(p.width == 3);
  CHECK(p.unit == "m");
}

TEST_CASE("a failed case write leaves nothing behind", "[results]") {
  TempDir tmp;
  const CaseSpec spec = make_spec(0, 5e-4);
  const CaseRecord record = make_record(spec);

  SECTION("inconsistent history") {
    History h = make_history(4);
    h.values[1].pop_back();
    const fs::path file = tmp.path() / "bad.h5";
    CHECK_THROWS_AS(write_case_file(file, spec, record, h, Json::object()), std::runtime_error);
    CHECK(entries(tmp.path()).empty());
  }
  SECTION("the signal twice: HDF5 fails half-way, the error names the file") {
    History h = make_history(4);
    h.signals.push_back(h.signals[0]);
    h.values.push_back(h.values[0]);
    const fs::path file = tmp.path() / "twice.h5";
    CHECK_THROWS_WITH(write_case_file(file, spec, record, h, Json::object()),
                      Catch::Contains(file.string()));
    CHECK(entries(tmp.path()).empty());
  }
  SECTION("parent is a regular file") {
    std::ofstream(tmp.path() / "plain") << "x";
    CHECK_THROWS_AS(write_case_file(tmp.path() / "plain" / "case.h5", spec, record, make_history(2),
                                    Json::object()),
                    std::runtime_error);
    CHECK(entries(tmp.path()) == std::vector<std::string>{"plain"});
  }
}

TEST_CASE("missing and corrupt case files read as absent", "[results]") {
  TempDir tmp;
  CHECK_FALSE(read_case_record(tmp.path() / "missing.h5").has_value());
  CHECK_FALSE(read_case_record(tmp.path()).has_value());  // a directory

  const fs::path garbage = tmp.path() / "garbage.h5";
  {
    std::ofstream out(garbage, std::ios::binary);
    for (int i = 0; i < 4096; ++i) out.put(static_cast<char>((i * 37 + 11) % 256));
  }
  CHECK_FALSE(read_case_record(garbage).has_value());

  const fs::path empty = tmp.path() / "empty.h5";
  std::ofstream(empty).close();
  CHECK_FALSE(read_case_record(empty).has_value());

  // a valid file cut short, as a crash during a copy would leave it
  const CaseSpec spec = make_spec(0, 5e-4);
  const fs::path good = tmp.path() / "good.h5";
  write_case_file(good, spec, make_record(spec), make_history(2000), Json::object());
  REQUIRE(read_case_record(good).has_value());
  const auto size = fs::file_size(good);
  const fs::path cut = tmp.path() / "cut.h5";
  fs::copy_file(good, cut);
  fs::resize_file(cut, size / 2);
  CHECK_FALSE(read_case_record(cut).has_value());
}

TEST_CASE("case files written from several threads are all complete", "[results]") {
  TempDir tmp;
  constexpr int kThreads = 4, kPerThread = 5;
  std::vector<std::thread> threads;
  std::atomic<int> failures{0};
  for (int t = 0; t < kThreads; ++t)
    threads.emplace_back([&, t] {
      for (int k = 0; k < kPerThread; ++k) {
        const CaseSpec spec = make_spec(t * kPerThread + k, 5e-4);
        try {
          write_case_file(tmp.path() / (spec.id + ".h5"), spec, make_record(spec),
                          make_history(500), Json::object());
          const auto back = read_case_record(tmp.path() / (spec.id + ".h5"));
          if (!back || back->index != spec.index) ++failures;
        } catch (...) {
          ++failures;
        }
      }
    });
  for (auto& th : threads) th.join();
  CHECK(failures == 0);
  CHECK(entries(tmp.path()).size() == static_cast<std::size_t>(kThreads * kPerThread));
}

TEST_CASE("the summary has one header line and one line per case", "[results]") {
  TempDir tmp;
  const Study study = make_study(tmp.path());
  std::vector<CaseRecord> rows;
  for (const CaseSpec& c : study.cases) rows.push_back(make_record(c));
  const fs::path dir = tmp.path() / "out";

  summarise(dir, study, rows);

  CHECK(entries(dir) == std::vector<std::string>{"summary.csv", "summary.h5"});
  const auto lines = lines_of(dir / "summary.csv");
  REQUIRE(lines.size() == 3);

  std::string header =
      "case_id,case_index,scene,parameters.contact.clearance,status,message,t_reached_s,"
      "wall_time_s,"
      "steps_accepted,steps_rejected,rhs_calls,friction_switches,started_utc,finished_utc";
  for (const MetricSpec& m : metric_catalogue()) header += "," + std::string(m.name);
  CHECK(lines[0] == header);

  // first row: the id, index, scene, the coordinate as the shortest decimal that reads back as
  // the same double (5e-4 is 0.0005, not %.17g's 0.00050000000000000001), empty message
  CHECK(lines[1].rfind(rows[0].id + ",0," + study.cases[0].scene +
                           ",0.0005,ok,,0.25,1.5,12345678901,17,98765,0,"
                           "2024-05-01T10:00:00Z,2024-05-01T10:00:02Z,",
                       0) == 0);
  // every metric reads back exactly (0.125 i + 1e-17 needs 17 digits for i = 0 only)
  {
    std::vector<std::string> fields;
    std::stringstream in(lines[1]);
    for (std::string f; std::getline(in, f, ',');) fields.push_back(f);
    // the columns before the metrics: those of the header less one per metric
    const std::size_t first_metric =
        static_cast<std::size_t>(std::count(header.begin(), header.end(), ',')) + 1 -
        metric_catalogue().size();
    REQUIRE(fields.size() == first_metric + rows[0].metrics.size());
    for (std::size_t i = 0; i < rows[0].metrics.size(); ++i) {
      INFO("metric " << i << ": " << fields[first_metric + i]);
      if (std::isnan(rows[0].metrics[i]))
        CHECK(fields[first_metric + i] == "nan");
      else
        CHECK(std::stod(fields[first_metric + i]) == rows[0].metrics[i]);
    }
    CHECK(fields[first_metric] == "1e-17");
  }
  // second row: a message with a comma and quotes is quoted, quotes doubled
  CHECK(lines[2].find(",penetration_limit,\"penetration, \"\"deep\"\", at t = 0.01 s\",") !=
        std::string::npos);
  // NaN metrics are written as nan
  CHECK(lines[1].find(",nan") != std::string::npos);

  SECTION("rewriting replaces both files, and no temporary file is left") {
    rows.pop_back();
    summarise(dir, study, rows);
    CHECK(entries(dir) == std::vector<std::string>{"summary.csv", "summary.h5"});
    CHECK(lines_of(dir / "summary.csv").size() == 2);
  }
}

TEST_CASE("a summary of no cases is just the header", "[results]") {
  TempDir tmp;
  Study study = make_study(tmp.path());
  study.cases.clear();
  summarise(tmp.path(), study, {});
  CHECK(entries(tmp.path()) == std::vector<std::string>{"summary.csv", "summary.h5"});
  CHECK(lines_of(tmp.path() / "summary.csv").size() == 1);
}

namespace {

/// A history whose values fill every bit pattern class (irrational fractions, signs, tiny and
/// huge magnitudes), over several chunks and a partial last chunk: 4096-row chunks, 9001 rows.
History varied_history(long long samples) {
  History h;
  h.samples = samples;
  h.signals = {SignalId::time, SignalId::ball_position};
  h.values.resize(2);
  for (long long i = 0; i < samples; ++i) {
    const double x = static_cast<double>(i);
    h.values[0].push_back(1e-4 * x);
    h.values[1].push_back(std::sin(x) * 1e-3);
    h.values[1].push_back(-std::exp(-x / 300.0) * 1e5);
    h.values[1].push_back(x * 1e-300);
  }
  return h;
}

/// The signal `name` of `file` as plain h5py reads it (no plugin), converted to float64 by
/// numpy: written to a raw file by /usr/bin/python3 and read back.
std::vector<double> read_with_h5py(const fs::path& file, const std::string& name,
                                   const fs::path& scratch) {
  const fs::path out = scratch / (name + ".f64");
  const std::string cmd =
      "/usr/bin/python3 -c \"import h5py, numpy as np, sys; "
      "f = h5py.File(sys.argv[1], 'r'); "
      "np.asarray(f['signals/' + sys.argv[2]][()], dtype='<f8').tofile(sys.argv[3])\" '" +
      file.string() + "' " + name + " '" + out.string() + "'";
  REQUIRE(std::system(cmd.c_str()) == 0);
  std::ifstream in(out, std::ios::binary);
  std::vector<double> v;
  double d;
  while (in.read(reinterpret_cast<char*>(&d), sizeof d)) v.push_back(d);
  return v;
}

}  // namespace

TEST_CASE("histories compressed off the lock read back exactly with HDF5, h5py and h5dump",
          "[results][output]") {
  TempDir tmp;
  const History h = varied_history(9001);
  struct Setting {
    int level;
    HistoryPrecision precision;
  };
  for (const Setting s :
       {Setting{0, HistoryPrecision::float64}, Setting{1, HistoryPrecision::float64},
        Setting{6, HistoryPrecision::float64}, Setting{12, HistoryPrecision::float64},
        Setting{6, HistoryPrecision::float32}, Setting{0, HistoryPrecision::float32}}) {
    const bool f32 = s.precision == HistoryPrecision::float32;
    INFO("compression_level " << s.level << ", history_precision " << to_string(s.precision));
    CaseSpec spec = make_spec(0, 5e-4);
    spec.output.compression_level = s.level;
    spec.output.history_precision = s.precision;
    const fs::path file = tmp.path() / ("level" + std::to_string(s.level) +
                                        std::string(to_string(s.precision)) + ".h5");
    write_case_file(file, spec, make_record(spec), h, Json::object());
    for (std::size_t k = 0; k < h.signals.size(); ++k) {
      const std::string name(signal_spec(h.signals[k]).name);
      INFO("signal " << name);
      std::vector<double> want = h.values[k];
      if (f32)
        for (double& v : want) v = static_cast<double>(static_cast<float>(v));
      // the library's own reader (HDF5's filter pipeline decodes the chunks)
      const SignalData d = read_signal(file, name);
      CHECK(d.samples == 9001);
      CHECK(d.values == want);
      // plain h5py: the standard shuffle and deflate filters, no plugin
      CHECK(read_with_h5py(file, name, tmp.path()) == want);
    }
    // h5dump decodes every dataset
    const std::string dump = "h5dump '" + file.string() + "' > /dev/null 2>&1";
    CHECK(std::system(dump.c_str()) == 0);
  }
}

TEST_CASE("compression makes the histories smaller, float32 halves them", "[results][output]") {
  TempDir tmp;
  const History h = make_history(20000);  // smooth, compressible
  auto size_at = [&](int level, HistoryPrecision p) {
    CaseSpec spec = make_spec(0, 5e-4);
    spec.output.compression_level = level;
    spec.output.history_precision = p;
    const fs::path file = tmp.path() / "size.h5";
    write_case_file(file, spec, make_record(spec), h, Json::object());
    return static_cast<double>(fs::file_size(file));
  };
  const double raw = size_at(0, HistoryPrecision::float64);
  const double raw32 = size_at(0, HistoryPrecision::float32);
  const double packed = size_at(6, HistoryPrecision::float64);
  // 20000 x 4 doubles = 640 kB of values; float32 stores half of that, deflate much less
  CHECK(raw > 640e3);
  CHECK(raw32 < 0.55 * raw);
  CHECK(packed < 0.5 * raw);
}

TEST_CASE("numbers are written as the shortest decimal that reads back exactly", "[results]") {
  CHECK(shortest_decimal(2e-4) == "0.0002");
  CHECK(shortest_decimal(5e-4) == "0.0005");
  CHECK(shortest_decimal(0.1 + 0.2) == "0.30000000000000004");  // not 0.3: that is another double
  CHECK(shortest_decimal(1e-17) == "1e-17");
  CHECK(shortest_decimal(-1.25) == "-1.25");
  CHECK(shortest_decimal(12345678901.0) == "12345678901");
  CHECK(shortest_decimal(1.5e20) == "1.5e+20");
  CHECK(shortest_decimal(0.0) == "0");
  CHECK(shortest_decimal(std::numeric_limits<double>::quiet_NaN()) == "nan");
  CHECK(shortest_decimal(-std::numeric_limits<double>::infinity()) == "-inf");
  // every double reads back as itself: a deterministic sweep over bit patterns of all magnitudes
  std::uint64_t bits = 0x9E3779B97F4A7C15ull;
  int bad = 0;
  for (int i = 0; i < 200000; ++i) {
    bits ^= bits << 13, bits ^= bits >> 7, bits ^= bits << 17;  // xorshift64
    double v;
    std::memcpy(&v, &bits, sizeof v);
    if (!std::isfinite(v)) continue;
    const std::string s = shortest_decimal(v);
    if (std::strtod(s.c_str(), nullptr) != v || s.size() > 24) ++bad;
  }
  CHECK(bad == 0);
}

// ---------------------------------------------------------------------------------------------
// The summary as a stream (issue 16 item 6): records spooled on the disk, the table written a
// block of rows at a time

namespace {

/// `n` records of varied content: every status and message kind, NaN metrics, coordinates of
/// both kinds (a number, and for every seventh case a string), the slot in every number.
std::vector<CaseRecord> varied_records(std::size_t n) {
  std::vector<CaseRecord> rows;
  for (std::size_t i = 0; i < n; ++i) {
    CaseRecord r = make_record(make_spec(static_cast<long>(i), 1e-4 * static_cast<double>(i + 1)));
    r.id = rodend::fnv1a64_hex("case " + std::to_string(i));
    r.wall_time = 1.0 / static_cast<double>(i + 3);  // every bit of the double
    r.message = i % 5 == 1 ? "line one,\nline \"two\", \xC2\xB5m" : r.message;
    if (i % 7 == 3)
      r.coordinates["parameters.contact.law"] = "flores";
    else
      r.coordinates["parameters.contact.law"] = static_cast<double>(i);
    r.metrics[0] = std::ldexp(1.0, -1000) * static_cast<double>(i);  // a subnormal or zero
    rows.push_back(r);
  }
  return rows;
}

}  // namespace

TEST_CASE("the record spool gives back every record exactly, in case order", "[results][spool]") {
  TempDir tmp;
  const std::size_t n = 700;  // ~0.7 kB each: several 64 kB buffers go to the file
  const std::vector<CaseRecord> rows = varied_records(n);
  RecordSpool spool(tmp.path(), n + 5);
  // nothing of the spool is visible in the directory (anonymous file)
  CHECK(entries(tmp.path()).empty());
  // stored in a scrambled order, slots n..n+4 left empty, slot 10 stored twice (the last wins)
  CaseRecord first_10 = rows[10];
  first_10.status = RunStatus::ok;
  first_10.message = "superseded";
  spool.put(10, first_10);
  for (std::size_t k = 0; k < n; ++k)
    spool.put((k * 337) % n, rows[(k * 337) % n]);  // 337, n coprime
  CHECK(spool.size() == n);                         // the empty slots are no rows
  CHECK(spool.failed() == n - 1);  // make_record: case 0 ok, the others not (10 replaced)
  CHECK(spool.text_coordinates() == std::set<std::string>{"parameters.contact.law"});
  SECTION("a replaced record counts no longer") {
    RecordSpool two(tmp.path(), 2);
    CaseRecord r = rows[3];  // parameters.contact.law "flores": a text column; failed
    two.put(1, r);
    CHECK(two.text_coordinates() == std::set<std::string>{"parameters.contact.law"});
    CHECK(two.failed() == 1);
    r.coordinates["parameters.contact.law"] = 2.0;
    r.status = RunStatus::ok;
    two.put(1, r);
    CHECK(two.text_coordinates().empty());
    CHECK(two.failed() == 0);
    CHECK(two.size() == 1);
  }
  // read in blocks, as write_summary does: case order
  std::vector<CaseRecord> block;
  for (std::size_t begin = 0; begin < n; begin += 256) {
    const std::size_t end = std::min(n, begin + 256);
    spool.read(begin, end, block);
    REQUIRE(block.size() == end - begin);
    for (std::size_t k = begin; k < end; ++k) {
      INFO("row " << k);
      require_same_record(block[k - begin], rows[k]);
    }
  }
  CHECK(entries(tmp.path()).empty());
}

TEST_CASE("a summary of many blocks reads back row for row", "[results][spool]") {
  TempDir tmp;
  Study study = make_study(tmp.path());
  study.axis_keys = {"parameters.contact.clearance", "parameters.contact.law"};
  // whole blocks of 256 rows and a partial one; strings enough that HDF5's metadata cache
  // (1 MiB) evicts the group and column headers and reads them back from the file
  const std::size_t n = 6000;
  const std::vector<CaseRecord> rows = varied_records(n);
  RecordSpool spool(tmp.path(), n);
  for (std::size_t i = n; i-- > 0;) spool.put(i, rows[i]);  // last first
  const fs::path dir = tmp.path() / "out";
  write_summary(dir, study, spool, provenance(study));
  CHECK(entries(dir) == std::vector<std::string>{"summary.csv", "summary.h5"});
  CHECK(summary_csv_matches(dir));
  CHECK(lines_of(dir / "summary.csv").size() == n + 1 + n / 5);  // messages with a newline

  const SummaryTable t = read_summary(dir);
  REQUIRE(t.rows == n);
  CHECK(t.is_text("parameters.contact.law"));
  CHECK_FALSE(t.is_text("parameters.contact.clearance"));
  for (std::size_t i = 0; i < n; ++i) {
    INFO("row " << i);
    CHECK(t.texts.at("case_id")[i] == rows[i].id);
    CHECK(t.numbers.at("case_index")[i] == static_cast<double>(rows[i].index));
    CHECK(t.texts.at("message")[i] == rows[i].message);
    CHECK(t.numbers.at("wall_time_s")[i] == rows[i].wall_time);
    CHECK(t.numbers.at("parameters.contact.clearance")[i] ==
          rows[i].coordinates["parameters.contact.clearance"].get<double>());
    const Json& law = rows[i].coordinates["parameters.contact.law"];
    CHECK(t.texts.at("parameters.contact.law")[i] ==
          (law.is_string() ? law.get<std::string>() : law.dump()));
    const std::string m0(metric_catalogue()[0].name);
    CHECK(t.numbers.at(m0)[i] == rows[i].metrics[0]);
  }
  // the same table from the records stored in order, byte for byte in summary.csv
  const fs::path again = tmp.path() / "again";
  summarise(again, study, rows);
  std::ifstream a(dir / "summary.csv", std::ios::binary),
      b(again / "summary.csv", std::ios::binary);
  const std::string text_a((std::istreambuf_iterator<char>(a)), std::istreambuf_iterator<char>());
  const std::string text_b((std::istreambuf_iterator<char>(b)), std::istreambuf_iterator<char>());
  CHECK(text_a == text_b);
  // and summary.csv rewritten from summary.h5, a block at a time, is the same bytes again
  fs::remove(dir / "summary.csv");
  CHECK(repair_summary_csv(dir));
  std::ifstream c(dir / "summary.csv", std::ios::binary);
  CHECK(std::string((std::istreambuf_iterator<char>(c)), std::istreambuf_iterator<char>()) ==
        text_a);
}

TEST_CASE("a full disk while HDF5 writes summary.h5 is one message and leaves nothing",
          "[results][faults]") {
  TempDir tmp;
  const Study study = make_study(tmp.path());
  const std::vector<CaseRecord> rows = varied_records(600);
  const fs::path ref = tmp.path() / "ref";
  summarise(ref, study, rows);
  const auto csv_bytes = static_cast<long long>(fs::file_size(ref / "summary.csv"));
  const auto h5_bytes = static_cast<long long>(fs::file_size(ref / "summary.h5"));
  // the failure at several points of summary.h5: its superblock, the middle of the columns,
  // its last bytes (summary.csv and summary.h5 are written side by side, a block at a time:
  // each budget fails one of them)
  for (const long long extra : {0LL, 100LL, 4096LL, h5_bytes / 2, h5_bytes - 1}) {
    INFO("bytes the disk takes beyond summary.csv: " << extra);
    const fs::path dir = tmp.path() / ("full-" + std::to_string(extra));
    fs::create_directories(dir);
    RecordSpool spool(dir, rows.size());  // filled while there is room
    for (std::size_t i = 0; i < rows.size(); ++i) spool.put(i, rows[i]);
    {
      const WriteFailureInjection full(csv_bytes + extra);
      CHECK_THROWS_WITH(write_summary(dir, study, spool, provenance(study)),
                        Catch::Contains("cannot write summary file") &&
                            Catch::Contains("No space left on device"));
    }
    CHECK(entries(dir).empty());  // no summary, no temporary file
    // room again: the same call succeeds and reads back
    write_summary(dir, study, spool, provenance(study));
    CHECK(read_summary(dir).rows == rows.size());
    CHECK(summary_csv_matches(dir));
  }
}
