// Running a study: a case whose scene throws an exception that is not a numerical failure is
// stored as internal_error with the exception's message, and the other cases of the study go on.
#include <unistd.h>

#include <atomic>
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <new>
#include <sstream>
#include <stdexcept>
#include <string>

#include "core/scene.hpp"
#include "fixture.hpp"
#include "sweep/case_order.hpp"
#include "sweep/runner.hpp"

namespace fs = std::filesystem;
using rodend::test::TempDir;
using namespace rodend;

namespace {

constexpr double kFaultyClearance = 1e-3;  // [m] the grid case whose scene throws
constexpr double kThrowAfter = 5e-3;       // [s] ... once its derivatives are asked past this
constexpr const char* kWhat = "test scene: a bug in the derivatives";

/// The gravity-drop scene as the catalogue builds it, except that, for contact.clearance
/// kFaultyClearance, its derivatives throw std::logic_error past kThrowAfter (a bug, not a
/// numerical failure). Everything else is the wrapped scene's.
class FaultyScene final : public Scene {
 public:
  /// `out_of_memory`: throws std::bad_alloc instead (memory that ran out, not a bug)
  explicit FaultyScene(const ParameterSet& p, bool out_of_memory = false)
      : inner_(find_scene("gravity-drop")->make(p)),
        throw_after_(p.number("contact.clearance") == kFaultyClearance
                         ? kThrowAfter
                         : std::numeric_limits<double>::infinity()),
        out_of_memory_(out_of_memory) {}
  std::string_view name() const override { return inner_->name(); }
  Features features() const override { return inner_->features(); }
  int state_size() const override { return inner_->state_size(); }
  void initial_state(double* x) const override { inner_->initial_state(x); }
  void state_scale(double* s) const override { inner_->state_scale(s); }
  std::span<const int> quaternion_offsets() const override { return inner_->quaternion_offsets(); }
  std::span<const int> audit_offsets() const override { return inner_->audit_offsets(); }
  void derivatives(double t, const double* x, const DiscreteState& d, double* dxdt) const override {
    if (t > throw_after_ && out_of_memory_) throw std::bad_alloc();
    if (t > throw_after_) throw std::logic_error(kWhat);
    inner_->derivatives(t, x, d, dxdt);
  }
  int contact_count() const override { return inner_->contact_count(); }
  ContactGap contact_gap(int c, const double* x) const override {
    return inner_->contact_gap(c, x);
  }
  double contact_clearance(int c) const override { return inner_->contact_clearance(c); }
  double contact_radius(int c) const override { return inner_->contact_radius(c); }
  std::span<const SignalId> signals() const override { return inner_->signals(); }
  void outputs(double t, const double* x, const DiscreteState& d, SignalFrame& f) const override {
    inner_->outputs(t, x, d, f);
  }
  void step_outputs(double t, const double* x, const DiscreteState& d,
                    SignalFrame& f) const override {
    inner_->step_outputs(t, x, d, f);
  }
  ContactSnapshot contact_snapshot(int c, double t, const double* x,
                                   const DiscreteState& d) const override {
    return inner_->contact_snapshot(c, t, x, d);
  }
  EnergyTerms energy(double t, const double* x, const DiscreteState& d) const override {
    return inner_->energy(t, x, d);
  }

 private:
  std::unique_ptr<Scene> inner_;
  double throw_after_;
  bool out_of_memory_;
};

std::unique_ptr<Scene> make_faulty_scene(const ParameterSet& p) {
  return std::make_unique<FaultyScene>(p);
}

std::unique_ptr<Scene> make_out_of_memory_scene(const ParameterSet& p) {
  return std::make_unique<FaultyScene>(p, true);
}

std::unique_ptr<Scene> make_unbuildable_scene(const ParameterSet&) {
  throw std::runtime_error("test scene: cannot be built");
}

/// Three gravity drops, the middle one (clearance kFaultyClearance) on the faulty scene.
Study three_drops(const fs::path& dir, const std::string& method) {
  const std::string text = R"({"name": "faulty", "scene": "gravity-drop",
    "integrator": {"method": ")" +
                           method + R"(", "abs_tol": 1e-8, "rel_tol": 1e-8},
    "time": {"end": 0.02, "sample_interval": 1e-3},
    "grid": [{"key": "parameters.contact.clearance", "values": [5e-4, 1e-3, 2e-3]}]})";
  return parse_study_text(text, dir / "faulty.json", dir / "results");
}

}  // namespace

TEST_CASE("a case whose scene throws is internal_error; the other cases go on", "[runner]") {
  const std::string method = GENERATE(as<std::string>{}, "dopri5", "cvode_bdf");
  CAPTURE(method);
  TempDir tmp;
  const SceneFactoryOverride faulty("gravity-drop", &make_faulty_scene);
  const Study study = three_drops(tmp.path(), method);
  REQUIRE(study.cases.size() == 3);
  RunOptions opt;
  opt.progress = false;
  CHECK(run_study(study, opt) == 1);  // a case failed

  const SummaryTable t = read_summary(study.output_dir);
  REQUIRE(t.rows == 3);
  const auto& status = t.texts.at("status");
  const auto& message = t.texts.at("message");
  CHECK(status[0] == "ok");
  CHECK(status[2] == "ok");
  REQUIRE(status[1] == "internal_error");
  // the exception's message, and the time the run reached before it (the last accepted step)
  CHECK_THAT(message[1], Catch::Contains(kWhat) && Catch::Contains("internal error after t = "));
  const double t_reached = t.numbers.at("t_reached_s")[1];
  CHECK(t_reached > 0.0);
  CHECK(t_reached <= kThrowAfter);
  CHECK(t.numbers.at("t_reached_s")[0] == 0.02);

  // the case file says the same
  const auto rec = read_case_record(study.output_dir / "cases" / (study.cases[1].id + ".h5"));
  REQUIRE(rec.has_value());
  CHECK(rec->status == RunStatus::internal_error);
  CHECK(rec->message == message[1]);
  CHECK(rec->t_reached == t_reached);
}

TEST_CASE("memory running out in a case stops the run; no case is recorded as failed",
          "[runner][faults]") {
  const std::string method = GENERATE(as<std::string>{}, "dopri5", "cvode_bdf");
  CAPTURE(method);
  TempDir tmp;
  const Study study = three_drops(tmp.path(), method);
  const fs::path faulty = study.output_dir / "cases" / (study.cases[1].id + ".h5");
  RunOptions opt;
  opt.progress = false;
  {
    const SceneFactoryOverride oom("gravity-drop", &make_out_of_memory_scene);
    History h;
    CHECK_THROWS_AS(run_case(study.cases[1], h), std::bad_alloc);  // not internal_error
    std::string what;
    try {
      run_study(study, opt);
    } catch (const OutOfMemory& e) {
      what = e.what();
    }
    CHECK_THAT(what, Catch::Contains("out of memory") &&
                         Catch::Contains("1 of 3 case(s) complete") &&
                         Catch::Contains("resume with: " + resume_command(study, opt)) &&
                         Catch::Contains("--results-root"));
    CHECK_FALSE(fs::exists(faulty));
    CHECK_FALSE(fs::exists(study.output_dir / "summary.h5"));
  }
  CHECK(run_study(study, opt) == 0);  // the resume runs it, with memory
  const auto rec = read_case_record(faulty);
  REQUIRE(rec.has_value());
  CHECK(rec->status == RunStatus::ok);
}

TEST_CASE("the resume command names every option that changes what a run does", "[runner]") {
  TempDir tmp;
  const fs::path file = tmp.path() / "my study.json", root = tmp.path() / "res root";
  const Study s = parse_study_text(
      R"({"name": "r", "scene": "gravity-drop", "time": {"end": 0.01, "sample_interval": 1e-3}})",
      file, root, {"description=it's", "time.end=0.02"});
  RunOptions o;
  CHECK(resume_command(s, o) == "rodend run '" + file.string() + "' --results-root '" +
                                    root.string() +
                                    "' --set 'description=it'\\''s' --set time.end=0.02");
  o.shard_index = 2;
  o.shard_count = 3;
  o.rerun_failed = true;
  CHECK_THAT(resume_command(s, o), Catch::EndsWith(" --shard 2/3 --rerun-failed"));
}

TEST_CASE("a scene that cannot be built at run time is internal_error", "[runner]") {
  TempDir tmp;
  const Study study = three_drops(tmp.path(), "dopri5");  // loaded with the real scene
  const SceneFactoryOverride unbuildable("gravity-drop", &make_unbuildable_scene);
  History h;
  const CaseRecord r = run_case(study.cases[0], h);
  CHECK(r.status == RunStatus::internal_error);
  CHECK_THAT(r.message, Catch::Contains("test scene: cannot be built") &&
                            Catch::Contains("outside the integration, at t = 0 s"));
  CHECK(r.t_reached == 0.0);
  CHECK(h.samples == 0);
  CHECK(h.signals.empty());
  for (double m : r.metrics) CHECK(std::isnan(m));
}

namespace {

std::vector<std::string> hidden_files(const fs::path& dir) {
  std::vector<std::string> out;
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    const std::string name = e.path().filename().string();
    if (name.rfind(".rodend", 0) != 0 && name.front() == '.') out.push_back(name);
  }
  return out;
}

std::string file_text(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

}  // namespace

TEST_CASE("a full disk (injected write failure) stops the run with one message",
          "[runner][faults]") {
  TempDir tmp;
  // the size of one case file (every case of the study has the same layout and sample count)
  const Study ref = three_drops(tmp.path() / "ref", "dopri5");
  RunOptions opt;
  opt.progress = false;
  REQUIRE(run_study(ref, opt) == 0);
  const auto case_size =
      static_cast<long long>(fs::file_size(ref.output_dir / "cases" / (ref.cases[0].id + ".h5")));
  // study.json goes first, through the same writer (and the same injected budget)
  const auto study_json = static_cast<long long>(fs::file_size(ref.output_dir / "study.json"));
  long long all_cases = 0;
  for (const CaseSpec& c : ref.cases)
    all_cases += static_cast<long long>(fs::file_size(ref.output_dir / "cases" / (c.id + ".h5")));

  const Study study = three_drops(tmp.path(), "dopri5");  // one thread: cases in grid order
  const fs::path cases = study.output_dir / "cases";
  SECTION("while writing a case file") {
    {
      const WriteFailureInjection full(study_json + case_size + 100);  // case 0, not case 1
      try {
        run_study(study, opt);
        FAIL("the run did not report the full disk");
      } catch (const std::runtime_error& e) {
        const std::string m = e.what();
        CHECK_THAT(m, Catch::Contains("No space left on device") &&
                          Catch::Contains((cases / (study.cases[1].id + ".h5")).string()) &&
                          Catch::Contains("1 of 3 case(s) complete") &&
                          Catch::Contains("Resume with: rodend run"));
      }
    }
    // earlier results intact, the failed and later cases absent, no temporary file left
    CHECK(verify_case_file(cases / (study.cases[0].id + ".h5")));
    const auto rec = read_case_record_strict(cases / (study.cases[0].id + ".h5"));
    REQUIRE(rec.has_value());
    CHECK(rec->status == RunStatus::ok);
    CHECK_FALSE(fs::exists(cases / (study.cases[1].id + ".h5")));
    CHECK_FALSE(fs::exists(cases / (study.cases[2].id + ".h5")));  // no case after the failure
    CHECK_FALSE(fs::exists(study.output_dir / "summary.h5"));
    CHECK(hidden_files(study.output_dir).empty());
  }
  SECTION("while writing the summary") {
    {
      const WriteFailureInjection full(study_json + all_cases + 100);  // not summary.h5
      // the message gives the count of complete cases and the resume command (issue 37 Why 7)
      CHECK_THROWS_WITH(run_study(study, opt), Catch::Contains("cannot write summary file") &&
                                                   Catch::Contains("No space left on device") &&
                                                   Catch::Contains("3 of 3 cases are complete") &&
                                                   Catch::Contains("Resume with: rodend run"));
    }
    for (const CaseSpec& c : study.cases) CHECK(verify_case_file(cases / (c.id + ".h5")));
    CHECK_FALSE(fs::exists(study.output_dir / "summary.h5"));
    CHECK_FALSE(fs::exists(study.output_dir / "summary.csv"));
    CHECK(hidden_files(study.output_dir).empty());
  }
  // once there is room again, the run resumes and completes
  REQUIRE(run_study(study, opt) == 0);
  CHECK(read_summary(study.output_dir).rows == 3);
  CHECK(summary_csv_matches(study.output_dir));
}

TEST_CASE("summary.csv of another run than summary.h5 is rewritten from it", "[runner][faults]") {
  TempDir tmp;
  const Study study = three_drops(tmp.path(), "dopri5");
  RunOptions opt;
  opt.progress = false;
  REQUIRE(run_study(study, opt) == 0);
  const fs::path csv = study.output_dir / "summary.csv";
  const std::string written = file_text(csv);
  REQUIRE(summary_csv_matches(study.output_dir));
  CHECK_FALSE(repair_summary_csv(study.output_dir));  // nothing to do
  // what a kill -9 between the two renames leaves: summary.h5 of this run, summary.csv of an
  // earlier one (or none)
  const std::string stale = GENERATE(as<std::string>{}, "", "case_id,case_index\n1,0\n");
  if (stale.empty()) {
    fs::remove(csv);
  } else {
    std::ofstream(csv, std::ios::binary) << stale;
  }
  CHECK_FALSE(summary_csv_matches(study.output_dir));
  CHECK(repair_summary_csv(study.output_dir));
  CHECK(file_text(csv) == written);  // byte for byte what the run wrote
  CHECK(summary_csv_matches(study.output_dir));
}

TEST_CASE("a case file with one byte changed fails its checksum", "[runner][faults]") {
  TempDir tmp;
  const Study study = three_drops(tmp.path(), "dopri5");
  RunOptions opt;
  opt.progress = false;
  REQUIRE(run_study(study, opt) == 0);
  const fs::path file = study.output_dir / "cases" / (study.cases[0].id + ".h5");
  REQUIRE(verify_case_file(file));
  std::string bytes = file_text(file);
  const std::size_t at = GENERATE(600, 5000, 20000);  // past the 512-byte checksum header
  REQUIRE(at < bytes.size());
  bytes[at] = static_cast<char>(bytes[at] ^ 0x01);
  std::ofstream(file, std::ios::binary | std::ios::trunc) << bytes;
  CHECK_THROWS_AS(verify_case_file(file), CorruptCaseFile);
  CHECK_THROWS_AS(read_case_record_strict(file), CorruptCaseFile);
  CHECK_FALSE(read_case_record(file).has_value());
}

// issue 37: a bit flipped anywhere, the checksum header's padding included, is caught
TEST_CASE("a case file with one bit flipped in its checksum header fails its checksum",
          "[runner][faults]") {
  TempDir tmp;
  const Study study = three_drops(tmp.path(), "dopri5");
  RunOptions opt;
  opt.progress = false;
  REQUIRE(run_study(study, opt) == 0);
  const fs::path file = study.output_dir / "cases" / (study.cases[0].id + ".h5");
  std::string bytes = file_text(file);
  const std::size_t at = GENERATE(0, 20, 30, 60, 100, 300, 511);  // the header, its padding
  const int bit = GENERATE(0, 5);
  bytes[at] = static_cast<char>(bytes[at] ^ (1 << bit));
  std::ofstream(file, std::ios::binary | std::ios::trunc) << bytes;
  CHECK_THROWS_AS(verify_case_file(file), CorruptCaseFile);
  CHECK_THROWS_WITH(read_signal(file, "time"),
                    Catch::Contains("corrupt case file") && Catch::Contains(file.string()));
  CHECK_THROWS_WITH(list_signals(file), Catch::Contains("corrupt case file"));
}

TEST_CASE("summary.h5 carries a checksum that every reader checks", "[runner][faults]") {
  TempDir tmp;
  const Study study = three_drops(tmp.path(), "dopri5");
  RunOptions opt;
  opt.progress = false;
  REQUIRE(run_study(study, opt) == 0);
  const fs::path file = study.output_dir / "summary.h5";
  REQUIRE(verify_summary_file(file));
  REQUIRE(read_summary(study.output_dir).rows == 3);
  std::string bytes = file_text(file);
  const std::size_t at = GENERATE(0, 40, 300, 600, 2000, 5000);
  REQUIRE(at < bytes.size());
  const std::size_t last = bytes.size() - 1;
  for (const std::size_t where : {at, last}) {
    std::string damaged = bytes;
    damaged[where] = static_cast<char>(damaged[where] ^ 0x10);
    std::ofstream(file, std::ios::binary | std::ios::trunc) << damaged;
    CHECK_THROWS_AS(verify_summary_file(file), CorruptFile);
    CHECK_THROWS_WITH(read_summary(study.output_dir),
                      Catch::Contains("corrupt summary file " + file.string()));
    // the pair check leaves a damaged summary.h5 to the readers; merge rebuilds it
    CHECK(summary_csv_matches(study.output_dir));
  }
  std::ostringstream report;
  CHECK(merge_study(study, report) == 0);
  CHECK(verify_summary_file(file));
}

TEST_CASE("merge refuses an intact case file under another case's name", "[runner][faults]") {
  TempDir tmp;
  const Study study = three_drops(tmp.path(), "dopri5");
  RunOptions opt;
  opt.progress = false;
  REQUIRE(run_study(study, opt) == 0);
  const fs::path cases = study.output_dir / "cases";
  const fs::path other = cases / (study.cases[1].id + ".h5");
  fs::copy_file(cases / (study.cases[0].id + ".h5"), other, fs::copy_options::overwrite_existing);
  const std::string summary = file_text(study.output_dir / "summary.h5");
  std::ostringstream report;
  CHECK(merge_study(study, report) == 1);
  CHECK_THAT(report.str(),
             Catch::Contains(other.string()) && Catch::Contains("holds case " + study.cases[0].id));
  CHECK(file_text(study.output_dir / "summary.h5") == summary);  // no summary written
  CHECK_THROWS_WITH(read_case_record_strict(other), Catch::Contains("holds case"));
}

TEST_CASE("a link planted at the lock file is refused, never written through", "[runner][faults]") {
  TempDir tmp;
  const Study study = three_drops(tmp.path(), "dopri5");
  RunOptions opt;
  opt.progress = false;
  REQUIRE(run_study(study, opt) == 0);
  const fs::path precious = tmp.path() / "precious.txt";
  std::ofstream(precious) << "precious\n";
  const fs::path lock = study.output_dir / ".rodend.lock";
  fs::remove(lock);
  const bool hard = GENERATE(false, true);
  if (hard)
    fs::create_hard_link(precious, lock);
  else
    fs::create_symlink(precious, lock);
  CHECK_THROWS_WITH(run_study(study, opt), Catch::Contains(lock.string()));
  std::ostringstream report;
  CHECK_THROWS_WITH(merge_study(study, report), Catch::Contains(lock.string()));
  CHECK(file_text(precious) == "precious\n");
}

namespace {

// the files of the three drops' first two cases: when the third case's scene is built, the
// second case's file is put over the first's, as another process could during a run
fs::path g_replaced, g_replacement;
bool g_by_rename = false;

std::unique_ptr<Scene> make_replacing_scene(const ParameterSet& p) {
  if (p.number("contact.clearance") == 2e-3) {
    if (g_by_rename) {  // a new file renamed over it
      const fs::path copy = g_replaced.parent_path() / "copy.tmp";
      fs::copy_file(g_replacement, copy);
      fs::rename(copy, g_replaced);
    } else {  // rewritten in place: the same inode, the same size
      fs::copy_file(g_replacement, g_replaced, fs::copy_options::overwrite_existing);
    }
  }
  return find_scene("gravity-drop")->make(p);
}

}  // namespace

TEST_CASE("a case file replaced by another case's during the run is noticed before the summary",
          "[runner][faults]") {
  TempDir tmp;
  const Study study = three_drops(tmp.path(), "dopri5");
  const fs::path cases = study.output_dir / "cases";
  g_replaced = cases / (study.cases[0].id + ".h5");
  g_replacement = cases / (study.cases[1].id + ".h5");
  g_by_rename = GENERATE(false, true);
  RunOptions opt;
  opt.progress = false;
  opt.threads = 1;  // the cases in grid order: 0 and 1 written when 2 starts
  {
    const SceneFactoryOverride replacing("gravity-drop", &make_replacing_scene);
    CHECK_THROWS_WITH(run_study(study, opt),
                      Catch::Contains("replaced during the run") &&
                          Catch::Contains(g_replaced.string()) &&
                          Catch::Contains("holds case " + study.cases[1].id) &&
                          Catch::Contains("2 of 3 case(s) complete") &&
                          Catch::Contains("Resume with: " + resume_command(study, opt)));
  }
  CHECK_FALSE(fs::exists(study.output_dir / "summary.h5"));
  // the resume lists the file that holds another case (never overwritten); once it is moved
  // away, the case runs again and the summary is written
  CHECK_THROWS_WITH(run_study(study, opt), Catch::Contains("holds case " + study.cases[1].id));
  fs::remove(g_replaced);
  CHECK(run_study(study, opt) == 0);
  CHECK(run_study(study, opt) == 0);
}

TEST_CASE("a run takes the cases of the largest sustained hinge moment first", "[runner]") {
  // sweep/case_order.hpp: the order only (longest first, stable), never the cases or their ids
  TempDir tmp;
  const Study s = parse_study_text(
      R"({"name": "order", "scene": "rod-end-kinematic",
          "parameters": {"hinge.kind": "constant"},
          "time": {"end": 0.01, "sample_interval": 1e-3},
          "grid": [{"key": "parameters.hinge.constant_moment",
                    "values": [0.0, 100.0, -300.0, 50.0, -100.0]}]})",
      tmp.path() / "order.json", tmp.path() / "results");
  const RunPlan plan = plan_run(s, RunOptions{});
  CHECK(plan.todo == std::vector<std::size_t>{2, 1, 4, 3, 0});  // equal |M|: grid order
  // without a prediction (no hinge moment in the scene), grid order
  const Study drops = three_drops(tmp.path(), "dopri5");
  std::vector<std::size_t> todo{0, 1, 2};
  order_largest_first(drops, todo);
  CHECK(todo == std::vector<std::size_t>{0, 1, 2});
}
