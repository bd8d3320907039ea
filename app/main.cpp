// rodend: command-line entry point.
//
// Exit codes: 0 success (every case ok); 1 a case failed (or, for compare, a difference);
// 2 bad input (the message names the file, the key path and what was expected).
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <new>
#include <sstream>

#include "app/analyze.hpp"
#include "app/report.hpp"
#include "core/integrator.hpp"
#include "core/scene.hpp"
#include "sweep/compare.hpp"
#include "sweep/menus.hpp"
#include "sweep/mpi_runner.hpp"
#include "sweep/runner.hpp"
#include "sweep/schema.hpp"
#include "sweep/study.hpp"

using namespace rodend;

namespace {

void print_dry_run(const Study& s) {
  std::string scenes;
  for (const auto& n : s.scenes) scenes += (scenes.empty() ? "" : ", ") + n;
  std::cout << "study " << s.name << ": scene" << (s.scenes.size() > 1 ? "s " : " ") << scenes
            << ", " << s.cases.size() << " case(s), results in " << s.output_dir.string() << "\n";
  if (s.design) std::cout << s.design->statistics();
  std::cout << "index\tcase_id\tmethod\tend_s";
  for (const auto& k : s.axis_keys) std::cout << "\t" << k;
  std::cout << "\n";
  for (std::size_t i = 0; i < s.cases.size(); ++i) {
    const CaseList::Row c = s.cases.row(i);
    std::cout << c.index << "\t" << c.id << "\t" << to_string(c.method) << "\t" << c.end_s;
    for (const auto& k : s.axis_keys) std::cout << "\t" << c.coordinates[k].dump();
    std::cout << "\n";
  }
}

int list_params(const std::string& scene, bool json) {
  const ParameterSet p = ParameterSet::defaults_for(scene);
  if (json) {
    std::cout << p.leaves().dump(2) << "\n";
    return 0;
  }
  const Json leaves = p.leaves();
  for (const auto& [path, leaf] : leaves.items()) {
    std::cout << path << " = " << leaf["value"].dump() << " [" << leaf["unit"].get<std::string>()
              << "]  (" << leaf["source"].get<std::string>();
    if (leaf.contains("note")) std::cout << ": " << leaf["note"].get<std::string>();
    std::cout << ")\n";
  }
  return 0;
}

int list_signals(bool markdown, bool json) {
  if (json) {
    Json out = Json::array();
    for (const auto& s : signal_catalogue())
      out.push_back(
          {{"name", s.name}, {"unit", s.unit}, {"width", s.width}, {"description", s.description}});
    std::cout << out.dump(2) << "\n";
    return 0;
  }
  if (markdown) std::cout << "| signal | unit | width | description |\n|---|---|---|---|\n";
  for (const auto& s : signal_catalogue()) {
    if (markdown)
      std::cout << "| `" << s.name << "` | " << s.unit << " | " << s.width << " | " << s.description
                << " |\n";
    else
      std::cout << s.name << " [" << s.unit << "] x" << s.width << ": " << s.description << "\n";
  }
  return 0;
}

int list_metrics(bool markdown, bool json) {
  if (json) {
    Json out = Json::array();
    for (const auto& m : metric_catalogue())
      out.push_back({{"name", m.name}, {"unit", m.unit}, {"description", m.description}});
    std::cout << out.dump(2) << "\n";
    return 0;
  }
  if (markdown) std::cout << "| metric | unit | description |\n|---|---|---|\n";
  for (const auto& m : metric_catalogue()) {
    if (markdown)
      std::cout << "| `" << m.name << "` | " << m.unit << " | " << m.description << " |\n";
    else
      std::cout << m.name << " [" << m.unit << "]: " << m.description << "\n";
  }
  return 0;
}

/// One menu (core/menus.hpp) as a table or JSON: its choices' names and descriptions.
void print_menu(const Menu& menu, bool markdown, Json* json) {
  const std::vector<MenuItem> items = menu.items();
  if (json) {
    Json list = Json::array();
    for (const MenuItem& i : items)
      list.push_back({{"name", i.name}, {"description", i.description}});
    (*json)[std::string(menu.id)] = {{"title", menu.title}, {"keys", menu.keys}, {"choices", list}};
    return;
  }
  if (markdown)
    std::cout << "\n## " << menu.title << " (`" << menu.id << "`)\n\nTaken by " << menu.keys
              << ".\n\n| name | description |\n|---|---|\n";
  else
    std::cout << menu.title << " (" << menu.id << "; " << menu.keys << "):\n";
  for (const MenuItem& i : items)
    if (markdown)
      std::cout << "| `" << i.name << "` | " << i.description << " |\n";
    else
      std::cout << "  " << i.name << ": " << i.description << "\n";
}

/// `rodend choices`: every menu (core/menus.def, sweep/menus.def), with the keys that take it.
int list_choices(bool markdown, bool as_json) {
  Json out = Json::object();
  for (const Menu& m : all_menus()) print_menu(m, markdown, as_json ? &out : nullptr);
  if (as_json) std::cout << out.dump(2) << "\n";
  return 0;
}

/// The command line: each subcommand and the values of its options.
struct Cli {
  CLI::App* run = nullptr;
  CLI::App* merge = nullptr;
  CLI::App* rdir = nullptr;
  CLI::App* schema = nullptr;
  CLI::App* report = nullptr;
  CLI::App* analyze = nullptr;
  CLI::App* calibrate = nullptr;
  CLI::App* scenes = nullptr;
  CLI::App* params = nullptr;
  CLI::App* signals = nullptr;
  CLI::App* metrics = nullptr;
  CLI::App* choices = nullptr;
  CLI::App* compare = nullptr;
  std::string study_file;
  RunOptions opt;
  bool dry_run = false, quiet = false;
  std::string results_root = "results";
  std::string shard;
  std::string report_dir, report_out;
  std::string scene_name;
  bool as_json = false, markdown = false;
  std::string cmp_a, cmp_b, tolerance_file;
  bool summary_only = false;
};

/// run, merge and results-dir: the commands that take a study.
void add_study_commands(CLI::App& app, Cli& c) {
  c.run = app.add_subcommand(
      "run",
      "Run a study (or a single case: a study with no grid). Cases already complete in "
      "the results directory are kept (resume); interrupted ones are rerun.");
  c.run->add_option("STUDY", c.study_file, "study file (JSON)")->required();
  c.run->add_option("--threads,-j", c.opt.threads, "OpenMP threads over cases")
      ->check(CLI::Range(1, 4096));
  c.run->add_flag("--dry-run", c.dry_run,
                  "resolve and validate every case, print the case count "
                  "and the resolved table, run nothing");
  c.run->add_flag("--rerun-failed", c.opt.rerun_failed,
                  "rerun cases whose stored status is a failure");
  c.run->add_flag("--quiet,-q", c.quiet, "no progress on stderr");
  c.run->add_flag("--wait", c.opt.wait,
                  "when another run of the same study holds its results directory, wait for it "
                  "instead of refusing");
  c.run->add_option("--results-root", c.results_root,
                    "where studies without an \"output\" key write (default: results)");
  c.run->add_option("--shard", c.shard,
                    "K/N: run only the K-th of N deterministic slices of the cases");
  c.run
      ->add_option("--set", c.opt.overrides,
                   "key.path=value: override one value of the study (repeatable; value is JSON, "
                   "else a string), e.g. --set parameters.contact.clearance=2e-4 --set "
                   "time.end=0.5; recorded in the written study.json and the provenance")
      ->expected(1)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  c.merge = app.add_subcommand(
      "merge",
      "Assemble results/<study>/summary.{h5,csv} from the case files of a study run in "
      "shards (--shard K/N) or by several jobs. STUDY is the study file or its results "
      "directory (with the study.json a run leaves there). Exit 0: every case has its "
      "file (failed cases included); 1: cases missing (listed on stderr, no summary "
      "written); 2: error.");
  c.merge->add_option("STUDY", c.study_file, "study file (JSON) or results directory")->required();
  c.merge->add_option("--results-root", c.results_root, "as for run");
  c.rdir = app.add_subcommand("results-dir", "Print the results directory of a study.");
  c.rdir->add_option("STUDY", c.study_file, "study file (JSON)")->required();
  c.rdir->add_option("--results-root", c.results_root, "as for run");
}

/// schema, report, analyze and calibrate.
void add_output_commands(CLI::App& app, Cli& c) {
  c.schema = app.add_subcommand(
      "schema",
      "Print the JSON Schema (draft 2020-12) of study files, generated from the loader's own "
      "lists of keys, settings, scenes, parameters and signals (for editors and checks).");
  c.report = app.add_subcommand(
      "report",
      "Write one self-contained HTML page for a study's results (RESULTS/report.html): the "
      "summary table with units, the figures of RESULTS/plots (draw them first with "
      "plots/plot_study.py) embedded as PNG, the study as run and its provenance.");
  c.report->add_option("RESULTS", c.report_dir, "a study's results folder")->required();
  c.report->add_option("--out", c.report_out, "the page to write (default RESULTS/report.html)");
  c.analyze = app.add_subcommand(
      "analyze",
      "Sensitivity and uncertainty analysis of a study with a sampled design "
      "(docs/uncertainty.md): Sobol' indices with intervals (saltelli), Morris screening "
      "(morris), a polynomial-chaos surrogate, sampling-based rankings (SRC, PRCC, Spearman), "
      "each metric's distribution and exceedance probabilities, history bands; prints per "
      "metric its spread and its factors ranked. Writes RESULTS/analysis/ and "
      "RESULTS/plots/analysis-*.png (which `rodend report` embeds). Runs the Python module "
      "rodend.analyze, whose options `rodend analyze --help` lists.");
  c.analyze->allow_extras();
  c.analyze->prefix_command();
  c.calibrate = app.add_subcommand(
      "calibrate",
      "Estimate unknown parameters (a clearance, a friction coefficient) from a measured record "
      "(docs/health-monitoring.md): a surrogate trained on a designed study of the test, "
      "checked on held-out cases, the posterior by Markov-chain Monte Carlo, a final full-model "
      "run at the posterior mode, and optionally the remaining life through the wear "
      "evolution. Runs the Python module rodend.calibrate, whose options `rodend calibrate "
      "--help` lists. "
      "Exit 0 ok, 1 a failed diagnostic, 2 bad input.");
  c.calibrate->allow_extras();
  c.calibrate->prefix_command();
  // --help goes to the Python module, which knows the options
  c.analyze->set_help_flag();
  c.calibrate->set_help_flag();
}

/// scenes, params, signals, metrics and choices: the catalogues.
void add_catalogue_commands(CLI::App& app, Cli& c) {
  c.scenes = app.add_subcommand("scenes", "List the scenes.");
  c.params =
      app.add_subcommand("params", "Print a scene's default parameters with units and provenance.");
  c.params->add_option("SCENE", c.scene_name, "scene name")->required();
  c.params->add_flag("--json", c.as_json, "as JSON");
  c.signals = app.add_subcommand("signals", "Print the catalogue of recorded signals.");
  c.signals->add_flag("--markdown", c.markdown, "as a Markdown table");
  c.signals->add_flag("--json", c.as_json, "as JSON");
  c.metrics = app.add_subcommand("metrics", "Print the summary metrics.");
  c.metrics->add_flag("--markdown", c.markdown, "as a Markdown table");
  c.metrics->add_flag("--json", c.as_json, "as JSON");
  c.choices = app.add_subcommand(
      "choices",
      "Print every menu of named choices (core/menus.def, sweep/menus.def): its names, what "
      "each means and the keys that take them.");
  c.choices->add_flag("--markdown", c.markdown, "as Markdown tables");
  c.choices->add_flag("--json", c.as_json, "as JSON");
  c.schema->add_flag("--markdown", c.markdown,
                     "instead, the settings of the study sections as a Markdown table");
}

void add_compare_command(CLI::App& app, Cli& c) {
  c.compare = app.add_subcommand(
      "compare",
      "Compare study results B against reference A: summary metrics with per-metric "
      "tolerances, histories pointwise up to the first impact and as envelopes after "
      "it. Missing or extra cases and signals are differences. Exit 0: equal within "
      "tolerance; 1: different; 2: error.");
  c.compare->add_option("A", c.cmp_a, "reference results folder (results/<study>)")->required();
  c.compare->add_option("B", c.cmp_b, "results folder to check")->required();
  c.compare->add_option("--tolerances", c.tolerance_file,
                        "tolerance file (JSON; see docs/results.md \"Comparing results\")");
  c.compare->add_flag("--summary-only", c.summary_only,
                      "compare summaries only (a reference kept without its case files)");
}

/// `rodend merge`: STUDY is a study file, or a results directory with the study as run.
int merge_command(const Cli& c) {
  Study study;
  std::filesystem::path arg = c.study_file;
  if (std::filesystem::is_directory(arg)) {               // a results directory: the study as run
    if (arg.filename().empty()) arg = arg.parent_path();  // a trailing slash
    study = load_study(arg / "study.json", c.results_root);
    if (!study.source.contains("name")) study.name = arg.filename().string();
    study.output_dir = arg;
  } else {
    study = load_study(arg, c.results_root);
  }
  return merge_study(study, std::cerr);
}

/// `rodend run`: the cases of a study (of one shard), under MPI when launched by it.
int run_command(Cli& c, const mpi::Session& mpi_session) {
  RunOptions& opt = c.opt;
  if (!c.shard.empty()) {
    int k = 0, n = 0;
    char slash = 0;
    std::istringstream in(c.shard);
    if (!(in >> k >> slash >> n) || slash != '/' || n < 1 || k < 1 || k > n || !in.eof())
      throw InputError("--shard", "expected K/N with 1 <= K <= N, got '" + c.shard + "'");
    opt.shard_index = k;
    opt.shard_count = n;
  }
  if (mpi_session.size() > 1) {
    opt.progress = !c.quiet && mpi_session.rank() == 0;
    return mpi::run_study_mpi(mpi_session, c.study_file, c.results_root, opt);
  }
  const Study study = load_study(c.study_file, c.results_root, opt.overrides);
  if (c.dry_run) {
    print_dry_run(study);
    return 0;
  }
  opt.progress = !c.quiet;
  const int rc = run_study(study, opt);
  // only when a summary was written (0: every case ok, 1: some failed); a run stopped by a
  // signal has said where its cases are and how to resume
  if (rc == 0 || rc == 1) std::cerr << "rodend: results in " << study.output_dir.string() << "\n";
  return rc;
}

/// The subcommand given on the command line.
int dispatch(Cli& c, const mpi::Session& mpi_session) {
  if (*c.scenes) {
    for (const auto& s : scene_catalogue()) std::cout << s.name << "\t" << s.summary << "\n";
    return 0;
  }
  if (*c.params) return list_params(c.scene_name, c.as_json);
  if (*c.analyze) return exec_analyze(c.analyze->remaining());
  if (*c.calibrate) return exec_calibrate(c.calibrate->remaining());
  if (*c.report) {
    std::cout << write_report(c.report_dir, c.report_out).string() << "\n";
    return 0;
  }
  if (*c.schema) {
    std::cout << (c.markdown ? study_settings_markdown() : study_schema().dump(2) + "\n");
    return 0;
  }
  if (*c.signals) return list_signals(c.markdown, c.as_json);
  if (*c.metrics) return list_metrics(c.markdown, c.as_json);
  if (*c.choices) return list_choices(c.markdown, c.as_json);
  if (*c.compare) {
    CompareSettings cs;
    if (!c.tolerance_file.empty()) cs = load_tolerances(c.tolerance_file);
    cs.summary_only = c.summary_only;
    return compare_studies(c.cmp_a, c.cmp_b, cs, std::cout);
  }
  if (*c.merge) return merge_command(c);
  if (*c.rdir) {
    std::cout << load_study(c.study_file, c.results_root).output_dir.string() << "\n";
    return 0;
  }
  if (*c.run) return run_command(c, mpi_session);
  return 0;
}

}  // namespace

int rodend_main(int argc, char** argv) {
  CLI::App app{
      "rodend: batch simulator for degraded rod-ends (spherical clearance joints) in "
      "flight-control actuation.\n\n"
      "A study file (JSON) names a scene, parameter overrides by dotted key path, an optional "
      "grid over parameters and integrator settings, the integrator, the end time, the sample "
      "interval and the signals to record. `rodend run` resolves and validates every case, "
      "runs them in parallel and writes results/<study>/: one HDF5 file per case "
      "(cases/<id>.h5: histories under /signals with CF `units` and `long_name` attributes "
      "and the time axis as a netCDF dimension, the resolved "
      "parameters, the integrator settings, status, wall time, step and right-hand-side "
      "counts, metrics) and a summary table (summary.h5, summary.csv). See README.md.\n\n"
      "Exit codes: 0 ok, 1 a case failed, 2 bad input.",
      "rodend"};
  app.require_subcommand(1);
  app.set_version_flag("--version", std::string(RODEND_VERSION) + " (" + RODEND_GIT_REVISION + ")");
  Cli c;
  add_study_commands(app, c);
  add_output_commands(app, c);
  add_catalogue_commands(app, c);
  add_compare_command(app, c);
  // the exit-code table (README "Command line"): a command line CLI11 cannot parse is bad
  // input, 2, like every other (CLI11's own codes, 105-109, are not rodend's); help is 0
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;
  }
  // MPI only for `rodend run` started by an MPI launcher (mpirun, srun): a plain run never
  // initialises MPI (Open MPI's singleton start costs about 0.6 s and refuses root).
  const mpi::Session mpi_session(*c.run && !c.dry_run && mpi::launched());
  try {
    return dispatch(c, mpi_session);
  } catch (const InputError& e) {
    std::cerr << "rodend: error: " << e.what() << "\n";
    return 2;
  } catch (const std::bad_alloc& e) {
    // memory ran out (sweep::OutOfMemory names the complete cases and the resume command).
    // Ended at once, without the handlers at exit: HDF5's own cleanup crashes on what an
    // allocation that failed inside it left behind, and nothing else is left to flush
    std::cerr << "rodend: error: " << e.what() << "\n";
    std::cout.flush();
    std::fflush(nullptr);
    std::_Exit(2);
  } catch (const std::exception& e) {
    std::cerr << "rodend: error: " << e.what() << "\n";
    return 2;
  }
}

// Out of memory anywhere, the command line's own set-up included: one message that allocates
// nothing, exit 2 (README "Command line"; tests/cli/test_alloc_failures.py).
int main(int argc, char** argv) {
  try {
    return rodend_main(argc, argv);
  } catch (const std::bad_alloc&) {
    static const char msg[] = "rodend: error: out of memory\n";
    const ssize_t w = ::write(STDERR_FILENO, msg, sizeof msg - 1);
    (void)w;
    return 2;
  }
}
