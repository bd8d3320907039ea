// The subcommands of the `rodend` command line, each one function that registers it with CLI11:
// its options, its help text and its action (a CLI11 callback, run once the whole command line
// is parsed). The catalogue app/commands.def lists them in the order `rodend --help` shows them;
// adding a subcommand is one line there and its function in the file of its family
// (scripts/prove-command.sh proves it).
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

// one declaration per line of the catalogue
#define RODEND_COMMAND(function) void function(CLI::App& app, Outcome& out);
#include "app/commands.def"
#undef RODEND_COMMAND

}  // namespace rodend::cli
