// Stop signals (SIGINT, SIGTERM) while rodend runs cases: one process-wide handler and one
// record of the signal, installed by the first scope to open and replaced by what it found when
// the last one closes, whatever the order in which scopes of different threads (two Python
// threads, a run_study and a run_case) open and close.
#pragma once

#include <atomic>
#include <chrono>
#include <string>

namespace rodend {

/// What a second stop signal prints before it ends a batch run at once: the count of complete
/// cases and the command to resume, composed before the run, so that the handler only formats
/// the count and copies bytes (async-signal-safe).
struct StopReport {
  std::atomic<long> complete{0};  ///< cases complete (earlier runs' included), kept current
  long in_scope = 0;              ///< cases of the run (of its shard)
  /// after "N of M case(s) complete": " in DIR; ... Resume with: CMD\n"
  std::string tail;
};
static_assert(std::atomic<long>::is_always_lock_free);

class StopSignalScope {
 public:
  /// What a stop signal does while a scope of the kind is open (both, when both are):
  ///  - batch: a run of cases (run_study, `rodend run`): SIGINT or SIGTERM stops the run from
  ///    taking new cases (stop_signal(); the cases in flight finish and are written) and says
  ///    so on stderr; a second signal prints the `report` (the count of complete cases and the
  ///    resume command) and ends the process at once, by that signal; without a report, the
  ///    default action is restored at the first (the second ends the process);
  ///  - one_case: the Python module's run_case: SIGINT interrupts the case at its next sample
  ///    (case_interrupt(), sweep/case_observer.hpp), SIGTERM is left alone;
  ///  - rank: a rank of a distributed run (sweep/mpi_runner.cpp), which its watch thread ends at
  ///    once: SIGINT or SIGTERM is recorded (the first one; stop_signal()) and wakes
  ///    wait_for_stop_signal(), nothing is written, the handler stays, and the system calls of
  ///    the rank's other threads go on (SA_RESTART) until it ends.
  enum class Kind { batch, one_case, rank };
  /// `quiet_notice` (batch only): the run's messages go elsewhere (Python's logging), so the
  /// handler's "stopping" notice is not written on file descriptor 2 for it. `report` (batch
  /// only; outlives the scope): what a second signal prints.
  explicit StopSignalScope(Kind kind, bool quiet_notice = false,
                           const StopReport* report = nullptr);
  ~StopSignalScope();
  StopSignalScope(const StopSignalScope&) = delete;
  StopSignalScope& operator=(const StopSignalScope&) = delete;

 private:
  Kind kind_;
  bool quiet_;
  const StopReport* report_;
};

/// The signal that stopped the batch runs (or the rank) since the first batch or rank scope
/// opened; 0: none.
int stop_signal();
/// The name of a stop signal as messages print it: "SIGINT" or "SIGTERM".
const char* stop_signal_name(int sig);

/// Waits until a stop signal arrives while a rank scope is open, wake_stop_signal_waiters() is
/// called or `timeout` passes, and returns stop_signal().
int wait_for_stop_signal(std::chrono::milliseconds timeout);
/// Ends the waits of wait_for_stop_signal() (a rank's watch thread, when it is to finish).
void wake_stop_signal_waiters();

}  // namespace rodend
