#include "sweep/stop_signals.hpp"

#include <semaphore.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <csignal>
#include <ctime>
#include <mutex>

#include "sweep/case_observer.hpp"

namespace rodend {
namespace {

std::atomic<int> g_stop_signal{0};
// open scopes of each kind; read by the handler (lock-free), written under g_mutex
std::atomic<int> g_batches{0}, g_cases{0}, g_ranks{0};
// open batch scopes whose messages go elsewhere (Python's logging): the handler's notice on file
// descriptor 2 is written only while some batch scope is not quiet
std::atomic<int> g_quiet_batches{0};
static_assert(std::atomic<int>::is_always_lock_free);
std::mutex g_mutex;
struct sigaction g_old_int {
}, g_old_term{};
// the report of the batch scope opened last that has one (a second signal prints it)
std::atomic<const StopReport*> g_report{nullptr};
static_assert(std::atomic<const StopReport*>::is_always_lock_free);
/// Posted by the handler in a rank (sem_post is async-signal-safe): wait_for_stop_signal.
struct Wake {
  sem_t sem;
  Wake() { sem_init(&sem, 0, 0); }
} g_wake;

void write_text(const char* text, std::size_t n) {
  while (n > 0) {
    const ssize_t w = ::write(STDERR_FILENO, text, n);
    if (w <= 0) return;
    text += w;
    n -= static_cast<std::size_t>(w);
  }
}

/// n in decimal, into `buf` (async-signal-safe); returns the digits' start.
char* decimal(long n, char (&buf)[24]) {
  char* p = buf + sizeof buf;
  const bool negative = n < 0;
  unsigned long u = negative ? 0UL - static_cast<unsigned long>(n) : static_cast<unsigned long>(n);
  do {
    *--p = static_cast<char>('0' + u % 10);
    u /= 10;
  } while (u > 0);
  if (negative) *--p = '-';
  return p;
}

/// "rodend: stopped at once by SIGINT: N of M case(s) complete<tail>" (async-signal-safe).
void write_report(int sig, const StopReport& r) {
  static const char head_int[] = "\nrodend: stopped at once by SIGINT: ";
  static const char head_term[] = "\nrodend: stopped at once by SIGTERM: ";
  if (sig == SIGINT)
    write_text(head_int, sizeof head_int - 1);
  else
    write_text(head_term, sizeof head_term - 1);
  char buf[24];
  const char* d = decimal(r.complete.load(), buf);
  write_text(d, static_cast<std::size_t>(buf + sizeof buf - d));
  static const char of[] = " of ";
  write_text(of, sizeof of - 1);
  d = decimal(r.in_scope, buf);
  write_text(d, static_cast<std::size_t>(buf + sizeof buf - d));
  static const char complete[] = " case(s) complete";
  write_text(complete, sizeof complete - 1);
  write_text(r.tail.data(), r.tail.size());
}

extern "C" void on_stop_signal(int sig) {
  if (sig == SIGINT && g_cases.load() > 0) case_interrupt().store(true);
  if (g_ranks.load() > 0) {  // the rank's watch thread ends it
    int none = 0;
    g_stop_signal.compare_exchange_strong(none, sig);
    sem_post(&g_wake.sem);
    return;
  }
  if (g_batches.load() == 0) return;
  const bool loud = g_batches.load() > g_quiet_batches.load();
  int none = 0;
  if (!g_stop_signal.compare_exchange_strong(none, sig)) {  // the second: at once
    if (const StopReport* r = g_report.load(); r && loud) write_report(sig, *r);
    std::signal(sig, SIG_DFL);
    std::raise(sig);  // delivered as the handler returns: the process ends by the signal
    return;
  }
  static const char msg[] =
      "\nrodend: stopping: no new cases; the cases in flight finish and are written (signal "
      "again to stop at once)\n";
  if (loud) write_text(msg, sizeof msg - 1);
  // nothing to print at the second (Python's run_study): the default action ends the process
  if (!g_report.load()) std::signal(sig, SIG_DFL);
}

void install(int sig, struct sigaction* old, bool restart) {
  struct sigaction sa {};
  sa.sa_handler = on_stop_signal;
  sa.sa_flags = restart ? SA_RESTART : 0;
  sigemptyset(&sa.sa_mask);
  sigaction(sig, &sa, old);
}

std::atomic<int>& open_scopes(StopSignalScope::Kind kind) {
  using Kind = StopSignalScope::Kind;
  return kind == Kind::batch ? g_batches : kind == Kind::rank ? g_ranks : g_cases;
}

}  // namespace

StopSignalScope::StopSignalScope(Kind kind, bool quiet_notice, const StopReport* report)
    : kind_(kind), quiet_(kind == Kind::batch && quiet_notice), report_(report) {
  const std::lock_guard lock(g_mutex);
  if (kind == Kind::batch && report_) g_report.store(report_);
  if (quiet_) g_quiet_batches.fetch_add(1);
  const bool first = g_batches.load() + g_cases.load() + g_ranks.load() == 0;
  const bool restart = kind == Kind::rank;
  if (kind != Kind::one_case && g_batches.load() + g_ranks.load() == 0) {
    g_stop_signal.store(0);
    install(SIGTERM, &g_old_term, restart);
  }
  if (kind == Kind::one_case && g_cases.load() == 0) case_interrupt().store(false);
  open_scopes(kind).fetch_add(1);
  if (first) install(SIGINT, &g_old_int, restart);
}

StopSignalScope::~StopSignalScope() {
  const std::lock_guard lock(g_mutex);
  const int left = open_scopes(kind_).fetch_sub(1) - 1;
  if (report_) {
    const StopReport* mine = report_;
    g_report.compare_exchange_strong(mine, nullptr);
  }
  if (quiet_) g_quiet_batches.fetch_sub(1);
  if (kind_ != Kind::one_case && g_batches.load() + g_ranks.load() == 0)
    sigaction(SIGTERM, &g_old_term, nullptr);
  if (kind_ == Kind::one_case && left == 0) case_interrupt().store(false);
  if (g_batches.load() + g_cases.load() + g_ranks.load() == 0)
    sigaction(SIGINT, &g_old_int, nullptr);
}

int stop_signal() {
  return g_stop_signal.load();
}

const char* stop_signal_name(int sig) {
  return sig == SIGINT ? "SIGINT" : "SIGTERM";
}

int wait_for_stop_signal(std::chrono::milliseconds timeout) {
  timespec until{};
  clock_gettime(CLOCK_REALTIME, &until);
  const long long ns = until.tv_nsec + std::chrono::nanoseconds(timeout).count();
  until.tv_sec += static_cast<time_t>(ns / 1000000000LL);
  until.tv_nsec = static_cast<long>(ns % 1000000000LL);
  while (sem_timedwait(&g_wake.sem, &until) != 0 && errno == EINTR) {
  }
  return stop_signal();
}

void wake_stop_signal_waiters() {
  sem_post(&g_wake.sem);
}

}  // namespace rodend
