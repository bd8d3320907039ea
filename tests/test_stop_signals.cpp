// The one record of stop signals (sweep/stop_signals.hpp): what SIGINT and SIGTERM do while a
// batch scope (rodend run) or a rank scope (a rank of a distributed run) is open. The signals
// are raised in this thread: the handler runs before raise() returns.
#include <catch2/catch.hpp>
#include <chrono>
#include <csignal>

#include "sweep/stop_signals.hpp"

using namespace rodend;

namespace {

/// The handler installed for `sig` now.
void (*handler_of(int sig))(int) {
  struct sigaction now {};
  sigaction(sig, nullptr, &now);
  return now.sa_handler;
}

}  // namespace

TEST_CASE("a rank scope records the first stop signal, wakes its waiter and keeps its handler",
          "[signals]") {
  const auto before_int = handler_of(SIGINT), before_term = handler_of(SIGTERM);
  {
    const StopSignalScope rank(StopSignalScope::Kind::rank);
    CHECK(stop_signal() == 0);
    CHECK(wait_for_stop_signal(std::chrono::milliseconds(1)) == 0);
    REQUIRE(std::raise(SIGTERM) == 0);
    CHECK(stop_signal() == SIGTERM);
    // still installed (a batch scope's would be SIG_DFL now): a second signal is recorded, not
    // fatal, and the first one stays the rank's
    REQUIRE(handler_of(SIGTERM) != SIG_DFL);
    REQUIRE(std::raise(SIGINT) == 0);
    CHECK(stop_signal() == SIGTERM);
    // the handler woke the waiter: this returns at once (an hour when nothing posted)
    CHECK(wait_for_stop_signal(std::chrono::hours(1)) == SIGTERM);
  }
  // the handlers found are back once the scope closes
  CHECK(handler_of(SIGINT) == before_int);
  CHECK(handler_of(SIGTERM) == before_term);
  {
    const StopSignalScope rank(StopSignalScope::Kind::rank);
    CHECK(stop_signal() == 0);  // a new run starts unstopped
  }
}

TEST_CASE("a batch scope records a stop signal and leaves the next one to end the process",
          "[signals]") {
  const auto before_term = handler_of(SIGTERM);
  {
    const StopSignalScope batch(StopSignalScope::Kind::batch, true);
    CHECK(stop_signal() == 0);
    REQUIRE(std::raise(SIGTERM) == 0);
    CHECK(stop_signal() == SIGTERM);
    CHECK(handler_of(SIGTERM) == SIG_DFL);
  }
  CHECK(handler_of(SIGTERM) == before_term);
}
