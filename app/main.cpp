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

#include "app/commands.hpp"
#include "core/params.hpp"

using namespace rodend;

namespace {

/// The subcommands, in the order `rodend --help` lists them (app/commands.def).
constexpr cli::Command kCommands[] = {
#define RODEND_COMMAND(function) cli::function,
#include "app/commands.def"
#undef RODEND_COMMAND
};

const char* const kDescription =
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
    "Exit codes: 0 ok, 1 a case failed, 2 bad input.";

}  // namespace

int rodend_main(int argc, char** argv) {
  CLI::App app{kDescription, "rodend"};
  app.require_subcommand(1);
  app.set_version_flag("--version", std::string(RODEND_VERSION) + " (" + RODEND_GIT_REVISION + ")");
  cli::Outcome out;
  for (const cli::Command add : kCommands) add(app, out);
  // the subcommand's action runs inside parse, once the command line is parsed
  try {
    app.parse(argc, argv);
    return out.exit_code;
  } catch (const CLI::ParseError& e) {
    // the exit-code table (README "Command line"): a command line CLI11 cannot parse is bad
    // input, 2, like every other (CLI11's own codes, 105-109, are not rodend's); help is 0
    return app.exit(e) == 0 ? 0 : 2;
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
