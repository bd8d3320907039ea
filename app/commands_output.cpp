// `rodend schema`, `report`, `analyze`, `calibrate` and `compare`: the commands about outputs.
#include <iostream>
#include <memory>

#include "app/analyze.hpp"
#include "app/commands.hpp"
#include "app/report.hpp"
#include "sweep/compare.hpp"
#include "sweep/schema.hpp"

namespace rodend::cli {

void add_schema(CLI::App& app, Outcome&) {
  auto markdown = std::make_shared<bool>(false);
  CLI::App* c = app.add_subcommand(
      "schema",
      "Print the JSON Schema (draft 2020-12) of study files, generated from the loader's own "
      "lists of keys, settings, scenes, parameters and signals (for editors and checks).");
  c->add_flag("--markdown", *markdown,
              "instead, the settings of the study sections as a Markdown table");
  c->callback([markdown] {
    std::cout << (*markdown ? study_settings_markdown() : study_schema().dump(2) + "\n");
  });
}

void add_report(CLI::App& app, Outcome&) {
  auto dir = std::make_shared<std::string>();
  auto page = std::make_shared<std::string>();
  CLI::App* c = app.add_subcommand(
      "report",
      "Write one self-contained HTML page for a study's results (RESULTS/report.html): the "
      "summary table with units, the figures of RESULTS/plots (draw them first with "
      "plots/plot_study.py) embedded as PNG, the study as run and its provenance.");
  c->add_option("RESULTS", *dir, "a study's results folder")->required();
  c->add_option("--out", *page, "the page to write (default RESULTS/report.html)");
  c->callback([dir, page] { std::cout << write_report(*dir, *page).string() << "\n"; });
}

/// `rodend analyze` and `rodend calibrate` hand every argument, --help included, to their
/// Python module, which knows the options.
void pass_to_python(CLI::App* c) {
  c->allow_extras();
  c->prefix_command();
  c->set_help_flag();
}

void add_analyze(CLI::App& app, Outcome& out) {
  CLI::App* c = app.add_subcommand(
      "analyze",
      "Sensitivity and uncertainty analysis of a study with a sampled design "
      "(docs/uncertainty.md): Sobol' indices with intervals (saltelli), Morris screening "
      "(morris), a polynomial-chaos surrogate, sampling-based rankings (SRC, PRCC, Spearman), "
      "each metric's distribution and exceedance probabilities, history bands; prints per "
      "metric its spread and its factors ranked. Writes RESULTS/analysis/ and "
      "RESULTS/plots/analysis-*.png (which `rodend report` embeds). Runs the Python module "
      "rodend.analyze, whose options `rodend analyze --help` lists.");
  pass_to_python(c);
  c->callback([c, &out] { out.exit_code = exec_analyze(c->remaining()); });
}

void add_calibrate(CLI::App& app, Outcome& out) {
  CLI::App* c = app.add_subcommand(
      "calibrate",
      "Estimate unknown parameters (a clearance, a friction coefficient) from a measured record "
      "(docs/health-monitoring.md): a surrogate trained on a designed study of the test, "
      "checked on held-out cases, the posterior by Markov-chain Monte Carlo, a final full-model "
      "run at the posterior mode, and optionally the remaining life through the wear "
      "evolution. Runs the Python module rodend.calibrate, whose options `rodend calibrate "
      "--help` lists. "
      "Exit 0 ok, 1 a failed diagnostic, 2 bad input.");
  pass_to_python(c);
  c->callback([c, &out] { out.exit_code = exec_calibrate(c->remaining()); });
}

void add_compare(CLI::App& app, Outcome& out) {
  struct Args {
    std::string a, b, tolerance_file;
    bool summary_only = false;
  };
  auto a = std::make_shared<Args>();
  CLI::App* c = app.add_subcommand(
      "compare",
      "Compare study results B against reference A: summary metrics with per-metric "
      "tolerances, histories pointwise up to the first impact and as envelopes after "
      "it. Missing or extra cases and signals are differences. Exit 0: equal within "
      "tolerance; 1: different; 2: error.");
  c->add_option("A", a->a, "reference results folder (results/<study>)")->required();
  c->add_option("B", a->b, "results folder to check")->required();
  c->add_option("--tolerances", a->tolerance_file,
                "tolerance file (JSON; see docs/results.md \"Comparing results\")");
  c->add_flag("--summary-only", a->summary_only,
              "compare summaries only (a reference kept without its case files)");
  c->callback([a, &out] {
    CompareSettings cs;
    if (!a->tolerance_file.empty()) cs = load_tolerances(a->tolerance_file);
    cs.summary_only = a->summary_only;
    out.exit_code = compare_studies(a->a, a->b, cs, std::cout);
  });
}

}  // namespace rodend::cli
