// Profiles from data (issue 31 item 1; docs/inputs.md "Profiles from data"): the interpolants,
// a sampled built-in stroke reproducing the stroke's results, the case id following the file's
// content and not its path, and the file checks.
#include <cmath>
// Boost 1.74's pchip calls isnan unqualified (found by neither ADL nor its namespace for a
// double): name it where that lookup finds it
using std::isnan;
#include <boost/math/interpolators/pchip.hpp>
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <string>

#include "core/errors.hpp"
#include "core/scenes/drivers.hpp"
#include "core/scenes/input_kinds.hpp"
#include "fixture.hpp"
#include "sweep/profile.hpp"
#include "sweep/runner.hpp"
#include "sweep/study.hpp"

using namespace rodend;
using namespace rodend::test;
namespace fs = std::filesystem;

namespace {

/// Relative difference allowed between a result of the built-in stroke and of the stroke sampled
/// every 1 ms (the test below says where it comes from).
constexpr double kProfileReproduceRel = 1.5e-4;

/// The thesis stroke of the scenes (core/scenes/parts/stroke.part.json): +-60 mm, 1 s strokes,
/// 0.2 s holds, one cycle (2.4 s), raised-cosine.
RaisedCosineStroke thesis_stroke() {
  StrokeParams m;
  m.extension = m.retraction = 0.06;
  return RaisedCosineStroke(m);
}

/// Writes `motion` sampled every `h` seconds over [0, end] as a profile CSV.
void write_stroke_csv(const fs::path& file, const Input& motion, double h, double end) {
  std::ofstream out(file);
  out << "# the built-in raised-cosine stroke sampled every " << h << " s\n";
  out << "time [s],position [m]\n" << std::setprecision(17);
  const long n = std::lround(end / h);
  for (long i = 0; i <= n; ++i) out << i * h << "," << motion.at(i * h).value << "\n";
}

Study load(const fs::path& dir, const Json& doc) {
  return parse_study(doc, dir / "study.json", dir / "results");
}

/// A kinematic study of the thesis stroke, from the built-in shape or from a profile file.
Json stroke_study(const std::string& profile_file, const std::string& interpolation) {
  Json doc = {{"scene", "rod-end-kinematic"},
              {"parameters", {{"motion.extension", 0.06}, {"motion.retraction", 0.06}}},
              // pinned (not a preset): the integrator's own error on two step sequences must
              // stay well below the sampling's (see the test below)
              {"integrator",
               {{"method", "cvode_bdf"}, {"abs_tol", 1e-8}, {"rel_tol", 1e-8}, {"max_step", 1e-3}}},
              {"time", {{"end", 2.4}, {"sample_interval", 1e-3}}}};
  if (!profile_file.empty()) {
    doc["parameters"]["motion.shape"] = "profile";
    doc["parameters"]["motion.profile.file"] = profile_file;
    doc["parameters"]["motion.profile.interpolation"] = interpolation;
  }
  return doc;
}

CaseRecord run_first(const Study& s) {
  History h;
  CaseRecord r = run_case(s.cases[0], h);
  INFO(r.message);
  REQUIRE(r.status == RunStatus::ok);
  return r;
}

}  // namespace

TEST_CASE("profile interpolants: linear and pchip against boost and the data", "[profiles]") {
  auto d = std::make_shared<ProfileData>();
  d->time = {0.0, 0.5, 1.0, 1.7, 2.0, 3.0};
  d->value = {0.0, 1.0, 1.0, -2.0, -1.5, 4.0};
  compute_pchip_slopes(*d);
  ProfileInput in;
  in.data = d;
  // Boost's pchip (the same Fritsch-Carlson-Brodlie slopes) as the reference of value and rate
  boost::math::interpolators::pchip<std::vector<double>> ref(std::vector<double>(d->time),
                                                             std::vector<double>(d->value));
  in.interpolation = ProfileInput::Interpolation::pchip;
  for (double t = 0.0; t < 3.0; t += 0.01) {
    CAPTURE(t);
    CHECK(in.at(t).value == Approx(ref(t)).margin(1e-12));
    CHECK(in.at(t).rate == Approx(ref.prime(t)).margin(1e-10));
    // monotone: within each interval's two samples (no overshoot past 1.0 on [0.5, 1])
    CHECK(in.at(t).value <= 4.0);
    CHECK(in.at(t).value >= -2.0);
  }
  CHECK(in.at(0.75).value == Approx(1.0).margin(1e-15));  // flat between equal samples
  in.interpolation = ProfileInput::Interpolation::linear;
  CHECK(in.at(1.35).value == Approx(-0.5));
  CHECK(in.at(1.35).rate == Approx(-3.0 / 0.7));
  // past the end: hold the last value, or repeat with period 3 s; before the start: the first
  in.past_end = ProfileInput::PastEnd::hold;
  CHECK(in.at(5.0).value == 4.0);
  CHECK(in.at(-1.0).value == 0.0);
  in.past_end = ProfileInput::PastEnd::repeat;
  CHECK(in.at(4.35).value == Approx(in.at(1.35).value));
  CHECK(in.range() == std::pair<double, double>{-2.0, 4.0});
}

// The done-when test of issue 31: a profile file sampling the raised-cosine stroke every
// h = 1 ms reproduces the stroke's results. The tolerance comes from the interpolation error of
// that sampling. The stroke x(t) = a S(t/T) (a = 0.12 m for the retraction, T = 1 s) has
// |x'''| <= (2 pi)^2 a / T^3 = 4.7 m/s^3; pchip's slopes are second-order accurate on a uniform
// grid where the samples are monotone (and exact, 0, at the holds), so its errors are of the
// orders h^3 |x'''| = 4.7e-9 m in position and h^2 |x'''| = 4.7e-6 m/s in rate: bounded here by
// 2e-9 m and 1.2e-5 m/s (measured 1.5e-10 m and 1.6e-6 m/s). The kinematic scene is driven by
// that position and rate: a relative input error of at most 1.2e-5 / 0.24 m/s (the peak rate)
// = 5e-5. The results respond to it with a gain of a few: the peak contact force, the most
// sensitive, moved by 6.2e-3 for the 2e-3 relative rate error of a 10 ms sampling (a gain of
// 3; the other results by 1e-5 or less). The integrator (cvode_bdf at 1e-8, pinned) adds its
// own error on two slightly different step sequences, well below (at 1e-6, the balanced preset
// since the error norm's fixed length, it was 1.7e-4 on the peak contact force: above the bound).
// The bound, kProfileReproduceRel = 1.5e-4, is that gain of 3 times the input's bound
// (measured: 5.6e-6 on the peak contact force, at most 4.3e-7 on the other results; with dopri5
// 1e-7, the balanced preset until issue 34: 4.2e-6 and 2.2e-8; a 10 ms sampling fails it).
TEST_CASE("profiles: a sampled raised-cosine stroke reproduces the stroke", "[profiles]") {
  TempDir dir("profiles");
  const double h = 1e-3;
  const RaisedCosineStroke stroke = thesis_stroke();
  write_stroke_csv(dir.path() / "stroke.csv", stroke, h, 2.4);
  const Study built_in = load(dir.path(), stroke_study("", ""));
  const Study sampled = load(dir.path(), stroke_study("stroke.csv", "pchip"));
  // the interpolation error of the sampling, measured between the samples
  const Input& m = stroke;
  const InputPtr read = read_motion(sampled.cases[0].parameters, "motion");
  REQUIRE(dynamic_cast<const ProfileFromFile*>(read.get()));
  const ProfileInput& in = dynamic_cast<const ProfileFromFile&>(*read).profile();
  double pos_err = 0.0, rate_err = 0.0;
  for (double t = 0.0; t <= 2.4; t += h / 7.3) {
    pos_err = std::max(pos_err, std::abs(in.at(t).value - m.at(t).value));
    rate_err = std::max(rate_err, std::abs(in.at(t).rate - m.at(t).rate));
  }
  measured("pchip position error of h = 1 ms [m]", pos_err, 2e-9);
  measured("pchip rate error of h = 1 ms [m/s]", rate_err, 1.2e-5);
  CHECK(pos_err < 2e-9);
  CHECK(rate_err < 1.2e-5);

  const CaseRecord a = run_first(built_in), b = run_first(sampled);
  for (MetricId id : {MetricId::max_contact_force, MetricId::max_surface_angle,
                      MetricId::min_surface_angle, MetricId::final_surface_angle,
                      MetricId::wear_integral, MetricId::input_work, MetricId::max_eccentricity}) {
    const double x = a.metrics[static_cast<std::size_t>(id)];
    const double y = b.metrics[static_cast<std::size_t>(id)];
    CAPTURE(static_cast<int>(id), x, y);
    measured("sampled stroke, relative difference", std::abs(y - x) / std::abs(x),
             kProfileReproduceRel);
    CHECK(std::abs(y - x) <= kProfileReproduceRel * std::abs(x));
  }
}

TEST_CASE("profiles: a result does not depend on the sample interval", "[profiles]") {
  // the integrator reads the interpolant wherever it steps (dense output: its steps do not stop
  // at the sample times), so the histories' spacing changes no metric of the run
  TempDir dir("profiles");
  write_stroke_csv(dir.path() / "stroke.csv", thesis_stroke(), 1e-2, 2.4);
  Json doc = stroke_study("stroke.csv", "pchip");
  const CaseRecord fine = run_first(load(dir.path(), doc));
  doc["time"]["sample_interval"] = 1e-2;
  const CaseRecord coarse = run_first(load(dir.path(), doc));
  for (MetricId id : {MetricId::max_contact_force, MetricId::max_surface_angle,
                      MetricId::wear_integral, MetricId::input_work}) {
    CAPTURE(static_cast<int>(id));
    CHECK(coarse.metrics[static_cast<std::size_t>(id)] ==
          Approx(fine.metrics[static_cast<std::size_t>(id)]).epsilon(1e-12));
  }
}

TEST_CASE("profiles: the case id follows the file's content and not its path", "[profiles]") {
  TempDir dir("profiles");
  fs::create_directories(dir.path() / "sub");
  write_stroke_csv(dir.path() / "stroke.csv", thesis_stroke(), 0.01, 2.4);
  fs::copy_file(dir.path() / "stroke.csv", dir.path() / "sub" / "copy.csv");
  auto id_of = [&](const std::string& file) {
    return load(dir.path(), stroke_study(file, "pchip")).cases[0].id;
  };
  const std::string id = id_of("stroke.csv");
  CHECK(id_of("sub/copy.csv") == id);                        // another path, same bytes
  CHECK(id_of((dir.path() / "stroke.csv").string()) == id);  // absolute
  CHECK(id_of("sub/../stroke.csv") == id);                   // spelled otherwise
  CHECK(id_of("stroke.csv") != load(dir.path(), stroke_study("", "")).cases[0].id);
  // one sample changed by 1 um: a new id
  {
    std::ofstream out(dir.path() / "sub" / "copy.csv", std::ios::app);
    out << "2.41,-0.059999\n";
  }
  CHECK(id_of("sub/copy.csv") != id);
  // the results record the file by name and content
  const Study s = load(dir.path(), stroke_study("stroke.csv", "pchip"));
  REQUIRE(s.profiles.size() == 1);
  CHECK(s.profiles[0]["file"] == "stroke.csv");
  CHECK(s.profiles[0]["content_fnv1a64"].get<std::string>().size() == 16);
  const Json leaf = s.cases[0].parameters.leaves()["motion.profile.file"];
  CHECK(leaf["content_fnv1a64"] == s.profiles[0]["content_fnv1a64"]);
  CHECK(s.cases[0].canonical()["parameters"]["motion.profile.file"] ==
        "fnv1a64:" + s.profiles[0]["content_fnv1a64"].get<std::string>());
  // the study as run, loaded from its results folder (rodend merge), finds the file through
  // the profiles.json the run wrote there
  fs::create_directories(dir.path() / "as-run");
  std::ofstream(dir.path() / "as-run" / "profiles.json") << s.profiles.dump();
  const Study as_run = parse_study(stroke_study("stroke.csv", "pchip"),
                                   dir.path() / "as-run" / "study.json", dir.path() / "results");
  CHECK(as_run.cases[0].id == id);
}

TEST_CASE("profiles: cases without a profile keep their ids", "[profiles]") {
  // the profile keys enter the id only when a profile is in use: this id is the one this case
  // had before profiles existed (`rodend run --dry-run` of main at 0cfe71b). The integrator is
  // given as the balanced preset resolved to then (dopri5 1e-7), since the id covers the
  // resolved settings and the preset has changed since (issue 34).
  TempDir dir("profiles");
  Json doc = stroke_study("", "");
  doc["integrator"] = {
      {"method", "dopri5"}, {"abs_tol", 1e-7}, {"rel_tol", 1e-7}, {"max_step", 1e-3}};
  const CaseSpec c = load(dir.path(), doc).cases[0];
  CHECK(c.id == "14e66f28a8df5d01");
  CHECK_FALSE(c.canonical()["parameters"].contains("motion.profile.file"));
  CHECK_FALSE(c.canonical()["parameters"].contains("hinge.profile.column"));
}

TEST_CASE("profiles: a hinge moment from a file and the past-the-end rules", "[profiles]") {
  TempDir dir("profiles");
  {
    std::ofstream out(dir.path() / "moment.csv");
    out << "time [s],moment [N m]\n0,0\n0.5,100\n1.0,0\n";
  }
  Json doc = {{"scene", "rod-end-kinematic"},
              {"parameters",
               {{"hinge.kind", "profile"},
                {"hinge.profile.file", "moment.csv"},
                {"hinge.profile.interpolation", "linear"}}},
              {"time", {{"end", 2.4}, {"sample_interval", 1e-2}}}};
  CHECK_THROWS_WITH(load(dir.path(), doc),
                    Catch::Contains("parameters.hinge.profile.file: moment.csv: its last sample "
                                    "is at 1 s, before the run's end"));
  doc["parameters"]["hinge.profile.past_end"] = "repeat";
  const Study s = load(dir.path(), doc);
  const InputPtr hm = read_hinge(s.cases[0].parameters, "hinge");
  CHECK(hm->value(0.25, 0.0) == Approx(50.0));
  CHECK(hm->value(1.25, 0.0) == Approx(50.0));
  doc["parameters"]["hinge.profile.past_end"] = "hold";
  CHECK(read_hinge(load(dir.path(), doc).cases[0].parameters, "hinge")->value(2.0, 0.0) == 0.0);
}

TEST_CASE("profiles: an HDF5 profile reads as its CSV twin", "[profiles]") {
  // written by tests/bad_inputs/profiles/make-profiles.py: time [s] and position [m], with a
  // units attribute on each dataset; the same samples as good.csv
  const fs::path dir = fs::path(RODEND_SOURCE_DIR) / "tests" / "bad_inputs" / "profiles";
  ProfileRequest r{"good.h5", dir / "good.h5", "time", "position", "m"};
  const ProfileData h5 = read_profile_file(r);
  r.file = "good.csv", r.resolved = dir / "good.csv";
  const ProfileData csv = read_profile_file(r);
  CHECK(h5.time == csv.time);
  CHECK(h5.value == csv.value);
  CHECK(h5.content_hash != csv.content_hash);
}
