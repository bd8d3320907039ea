// The subcommands of the `rodend` command line, each one function that registers it with CLI11:
// its options, its help text and its action (a CLI11 callback, run once the whole command line
// is parsed). app/main.cpp lists them in the order `rodend --help` shows them; adding a
// subcommand is one line there and its function in the file of its family.
#pragma once

#include <CLI/CLI.hpp>
#include <optional>

#include "sweep/mpi_runner.hpp"

namespace rodend::cli {

/// What the action of the subcommand given sets: its exit code (0 ok, 1 a case failed or a
/// difference, 2 bad input), and for `rodend run` the MPI session, kept until the program ends.
struct Outcome {
  int exit_code = 0;
  std::optional<mpi::Session> mpi;
};

/// Registers one subcommand on the application; its action writes into the outcome.
using Command = void (*)(CLI::App& app, Outcome& out);

// run, merge and results-dir: the commands that take a study (app/commands_study.cpp)
void add_run(CLI::App& app, Outcome& out);
void add_merge(CLI::App& app, Outcome& out);
void add_results_dir(CLI::App& app, Outcome& out);

// schema, report, analyze, calibrate and compare: the commands about outputs
// (app/commands_output.cpp)
void add_schema(CLI::App& app, Outcome& out);
void add_report(CLI::App& app, Outcome& out);
void add_analyze(CLI::App& app, Outcome& out);
void add_calibrate(CLI::App& app, Outcome& out);
void add_compare(CLI::App& app, Outcome& out);

// scenes, params, signals, metrics and choices: the catalogues (app/commands_catalogue.cpp)
void add_scenes(CLI::App& app, Outcome& out);
void add_params(CLI::App& app, Outcome& out);
void add_signals(CLI::App& app, Outcome& out);
void add_metrics(CLI::App& app, Outcome& out);
void add_choices(CLI::App& app, Outcome& out);

}  // namespace rodend::cli
