#include "sweep/stop_signals.hpp"

#include <unistd.h>

#include <atomic>
#include <csignal>
#include <mutex>

#include "sweep/case_observer.hpp"

namespace rodend {
namespace {

std::atomic<int> g_stop_signal{0};
// open scopes of each kind; read by the handler (lock-free), written under g_mutex
std::atomic<int> g_batches{0}, g_cases{0};
// open batch scopes whose messages go elsewhere (Python's logging): the handler's notice on file
// descriptor 2 is written only while some batch scope is not quiet
std::atomic<int> g_quiet_batches{0};
static_assert(std::atomic<int>::is_always_lock_free);
std::mutex g_mutex;
struct sigaction g_old_int {
}, g_old_term{};

extern "C" void on_stop_signal(int sig) {
  if (sig == SIGINT && g_cases.load() > 0) case_interrupt().store(true);
  if (g_batches.load() == 0) return;
  g_stop_signal.store(sig);
  static const char msg[] =
      "\nrodend: stopping: no new cases; the cases in flight finish and are written (signal "
      "again to stop at once)\n";
  if (g_batches.load() > g_quiet_batches.load()) {
    const ssize_t w = ::write(STDERR_FILENO, msg, sizeof msg - 1);
    (void)w;
  }
  std::signal(sig, SIG_DFL);
}

void install(int sig, struct sigaction* old) {
  struct sigaction sa {};
  sa.sa_handler = on_stop_signal;
  sigemptyset(&sa.sa_mask);
  sigaction(sig, &sa, old);
}

}  // namespace

StopSignalScope::StopSignalScope(Kind kind, bool quiet_notice)
    : kind_(kind), quiet_(kind == Kind::batch && quiet_notice) {
  const std::lock_guard lock(g_mutex);
  if (quiet_) g_quiet_batches.fetch_add(1);
  const bool first = g_batches.load() + g_cases.load() == 0;
  if (kind == Kind::batch && g_batches.load() == 0) {
    g_stop_signal.store(0);
    install(SIGTERM, &g_old_term);
  }
  if (kind == Kind::one_case && g_cases.load() == 0) case_interrupt().store(false);
  (kind == Kind::batch ? g_batches : g_cases).fetch_add(1);
  if (first) install(SIGINT, &g_old_int);
}

StopSignalScope::~StopSignalScope() {
  const std::lock_guard lock(g_mutex);
  const int left = (kind_ == Kind::batch ? g_batches : g_cases).fetch_sub(1) - 1;
  if (quiet_) g_quiet_batches.fetch_sub(1);
  if (kind_ == Kind::batch && left == 0) sigaction(SIGTERM, &g_old_term, nullptr);
  if (kind_ == Kind::one_case && left == 0) case_interrupt().store(false);
  if (g_batches.load() + g_cases.load() == 0) sigaction(SIGINT, &g_old_int, nullptr);
}

int stop_signal() {
  return g_stop_signal.load();
}

}  // namespace rodend
