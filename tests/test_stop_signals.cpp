// The one record of stop signals (sweep/stop_signals.hpp): what SIGINT and SIGTERM do while a
// batch scope (rodend run) or a rank scope (a rank of a distributed run) is open. The signals
// are raised in this thread: the handler runs before raise() returns.
#include <sys/wait.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <chrono>
#include <csignal>
#include <string>

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

TEST_CASE("a batch scope records a stop signal; a second prints the report and ends the process",
          "[signals]") {
  const auto before_term = handler_of(SIGTERM);
  {
    const StopSignalScope batch(StopSignalScope::Kind::batch, true);
    CHECK(stop_signal() == 0);
    REQUIRE(std::raise(SIGTERM) == 0);
    CHECK(stop_signal() == SIGTERM);
    CHECK(handler_of(SIGTERM) == SIG_DFL);  // no report to print: the default action
  }
  CHECK(handler_of(SIGTERM) == before_term);
  // the second signal, in a child process (it ends the process), its stderr into a pipe
  int fds[2];
  REQUIRE(::pipe(fds) == 0);
  const pid_t pid = ::fork();
  REQUIRE(pid >= 0);
  if (pid == 0) {
    ::dup2(fds[1], STDERR_FILENO);
    StopReport report;
    report.complete = 3;
    report.in_scope = 7;
    report.tail = " in DIR; Resume with: CMD\n";
    const StopSignalScope batch(StopSignalScope::Kind::batch, false, &report);
    std::raise(SIGTERM);
    report.complete = 4;  // a case completed since
    std::raise(SIGTERM);
    ::_exit(0);  // not reached
  }
  ::close(fds[1]);
  std::string out;
  char buf[256];
  for (ssize_t n; (n = ::read(fds[0], buf, sizeof buf)) > 0;)
    out.append(buf, static_cast<std::size_t>(n));
  ::close(fds[0]);
  int status = 0;
  REQUIRE(::waitpid(pid, &status, 0) == pid);
  CHECK(WIFSIGNALED(status));
  CHECK(WTERMSIG(status) == SIGTERM);
  CHECK_THAT(out, Catch::Contains("rodend: stopping:") &&
                      Catch::EndsWith("rodend: stopped at once by SIGTERM: 4 of 7 case(s) "
                                      "complete in DIR; Resume with: CMD\n"));
}
