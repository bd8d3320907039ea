// `rodend run`, `rodend merge` and `rodend results-dir`: the commands that take a study.
#include <filesystem>
#include <iostream>
#include <memory>
#include <sstream>

#include "app/commands.hpp"
#include "sweep/runner.hpp"
#include "sweep/study.hpp"

namespace rodend::cli {

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

/// The options of `rodend run`.
struct RunArgs {
  std::string study_file;
  RunOptions opt;
  bool dry_run = false, quiet = false;
  std::string results_root = "results";
  std::string shard;
};

/// `rodend run`: the cases of a study (of one shard), under MPI when launched by it.
int run_command(RunArgs& a, Outcome& out) {
  // MPI only for a run started by an MPI launcher (mpirun, srun): a plain run never
  // initialises MPI (Open MPI's singleton start costs about 0.6 s and refuses root)
  const mpi::Session& mpi_session = out.mpi.emplace(!a.dry_run && mpi::launched());
  RunOptions& opt = a.opt;
  if (!a.shard.empty()) {
    int k = 0, n = 0;
    char slash = 0;
    std::istringstream in(a.shard);
    if (!(in >> k >> slash >> n) || slash != '/' || n < 1 || k < 1 || k > n || !in.eof())
      throw InputError("--shard", "expected K/N with 1 <= K <= N, got '" + a.shard + "'");
    opt.shard_index = k;
    opt.shard_count = n;
  }
  if (mpi_session.size() > 1) {
    opt.progress = !a.quiet && mpi_session.rank() == 0;
    return mpi::run_study_mpi(mpi_session, a.study_file, a.results_root, opt);
  }
  const Study study = load_study(a.study_file, a.results_root, opt.overrides);
  if (a.dry_run) {
    print_dry_run(study);
    return 0;
  }
  opt.progress = !a.quiet;
  const int rc = run_study(study, opt);
  // only when a summary was written (0: every case ok, 1: some failed); a run stopped by a
  // signal has said where its cases are and how to resume
  if (rc == 0 || rc == 1) std::cerr << "rodend: results in " << study.output_dir.string() << "\n";
  return rc;
}

}  // namespace

void add_run(CLI::App& app, Outcome& out) {
  auto a = std::make_shared<RunArgs>();
  CLI::App* c = app.add_subcommand(
      "run",
      "Run a study (or a single case: a study with no grid). Cases already complete in "
      "the results directory are kept (resume); interrupted ones are rerun.");
  c->add_option("STUDY", a->study_file, "study file (JSON)")->required();
  c->add_option("--threads,-j", a->opt.threads, "OpenMP threads over cases")
      ->check(CLI::Range(1, 4096));
  c->add_flag("--dry-run", a->dry_run,
              "resolve and validate every case, print the case count "
              "and the resolved table, run nothing");
  c->add_flag("--rerun-failed", a->opt.rerun_failed,
              "rerun cases whose stored status is a failure");
  c->add_flag("--quiet,-q", a->quiet, "no progress on stderr");
  c->add_flag("--wait", a->opt.wait,
              "when another run of the same study holds its results directory, wait for it "
              "instead of refusing");
  c->add_option("--results-root", a->results_root,
                "where studies without an \"output\" key write (default: results)");
  c->add_option("--shard", a->shard,
                "K/N: run only the K-th of N deterministic slices of the cases");
  c->add_option("--set", a->opt.overrides,
                "key.path=value: override one value of the study (repeatable; value is JSON, "
                "else a string), e.g. --set parameters.contact.clearance=2e-4 --set "
                "time.end=0.5; recorded in the written study.json and the provenance")
      ->expected(1)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  c->callback([a, &out] { out.exit_code = run_command(*a, out); });
}

void add_merge(CLI::App& app, Outcome& out) {
  auto study_file = std::make_shared<std::string>();
  auto results_root = std::make_shared<std::string>("results");
  CLI::App* c = app.add_subcommand(
      "merge",
      "Assemble results/<study>/summary.{h5,csv} from the case files of a study run in "
      "shards (--shard K/N) or by several jobs. STUDY is the study file or its results "
      "directory (with the study.json a run leaves there). Exit 0: every case has its "
      "file (failed cases included); 1: cases missing (listed on stderr, no summary "
      "written); 2: error.");
  c->add_option("STUDY", *study_file, "study file (JSON) or results directory")->required();
  c->add_option("--results-root", *results_root, "as for run");
  c->callback([study_file, results_root, &out] {
    // STUDY is a study file, or a results directory with the study as run
    Study study;
    std::filesystem::path arg = *study_file;
    if (std::filesystem::is_directory(arg)) {
      if (arg.filename().empty()) arg = arg.parent_path();  // a trailing slash
      study = load_study(arg / "study.json", *results_root);
      if (!study.source.contains("name")) study.name = arg.filename().string();
      study.output_dir = arg;
    } else {
      study = load_study(arg, *results_root);
    }
    out.exit_code = merge_study(study, std::cerr);
  });
}

void add_results_dir(CLI::App& app, Outcome&) {
  auto study_file = std::make_shared<std::string>();
  auto results_root = std::make_shared<std::string>("results");
  CLI::App* c = app.add_subcommand("results-dir", "Print the results directory of a study.");
  c->add_option("STUDY", *study_file, "study file (JSON)")->required();
  c->add_option("--results-root", *results_root, "as for run");
  c->callback([study_file, results_root] {
    std::cout << load_study(*study_file, *results_root).output_dir.string() << "\n";
  });
}

}  // namespace rodend::cli
