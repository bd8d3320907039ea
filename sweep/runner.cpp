#include "sweep/runner.hpp"

#include <fcntl.h>
#include <omp.h>
#include <pthread.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iostream>
#include <mutex>
#include <ostream>

#include "core/scene.hpp"
#include "sweep/case_observer.hpp"
#include "sweep/case_order.hpp"
#include "sweep/stop_signals.hpp"
#include "sweep/wear_evolution.hpp"

namespace rodend {
namespace fs = std::filesystem;

namespace {

std::string format_duration(double s) {
  char buf[32];
  if (s < 60)
    std::snprintf(buf, sizeof buf, "%.0fs", s);
  else if (s < 3600)
    std::snprintf(buf, sizeof buf, "%dm%02ds", static_cast<int>(s / 60), static_cast<int>(s) % 60);
  else
    std::snprintf(buf, sizeof buf, "%dh%02dm", static_cast<int>(s / 3600),
                  static_cast<int>(s / 60) % 60);
  return buf;
}

}  // namespace

void run_message(const RunEvents& events, const std::string& text) {
  if (events.message)
    events.message(text);
  else
    std::fprintf(stderr, "rodend: %s\n", text.c_str());
}

Progress::Progress(bool enabled, long total, long already, const RunEvents& events)
    : events_(events),
      enabled_(enabled),
      tty_(isatty(fileno(stderr)) != 0),
      total_(total),
      done_(already),
      start_(std::chrono::steady_clock::now()),
      already_(already) {
  if (enabled_ && already > 0)
    run_message(events_, std::to_string(already) + " of " + std::to_string(total) +
                             " cases already complete, " + std::to_string(total - already) +
                             " to run");
}

void Progress::case_done(bool failed) {
  if (!enabled_) return;
  std::lock_guard lock(mutex_);
  ++done_;
  if (failed) ++failed_;
  const double elapsed =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const long ran = done_ - already_;
  const double eta =
      ran > 0 ? elapsed / static_cast<double>(ran) * static_cast<double>(total_ - done_) : 0.0;
  if (events_.progress) {
    events_.progress(done_, total_, failed_, elapsed, eta);
  } else if (tty_) {
    std::fprintf(stderr, "\r[%ld/%ld] %ld failed, elapsed %s, ETA %s   ", done_, total_, failed_,
                 format_duration(elapsed).c_str(), format_duration(eta).c_str());
    if (done_ == total_) std::fprintf(stderr, "\n");
    line_open_ = done_ != total_;
  } else if (done_ == total_ || elapsed - last_print_ >= 10.0) {
    last_print_ = elapsed;
    std::fprintf(stderr, "rodend: %ld/%ld cases done, %ld failed, elapsed %s, ETA %s\n", done_,
                 total_, failed_, format_duration(elapsed).c_str(), format_duration(eta).c_str());
  }
  std::fflush(stderr);
}

void Progress::break_line() {
  std::lock_guard lock(mutex_);
  if (!line_open_) return;
  std::fprintf(stderr, "\n");
  std::fflush(stderr);
  line_open_ = false;
}

bool in_shard(const CaseSpec& c, const RunOptions& o) {
  return o.shard_count <= 1 || (c.index % o.shard_count) + 1 == o.shard_index;
}

namespace {

/// A case without its wear evolution: one run of its scene.
CaseRecord run_single_case(const CaseSpec& spec, History& history) {
  CaseRecord rec = start_record(spec);
  const auto t0 = std::chrono::steady_clock::now();
  const auto scene = make_scene(spec.scene, spec.parameters);
  rec.features = scene->features();
  CaseObserver obs(*scene, spec, &history);
  const RunResult r = simulate(*scene, spec.integrator, spec.time, obs, spec.health);
  rec.wall_time = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  rec.finished_utc = utc_now();
  rec.status = r.status;
  rec.message = r.message;
  rec.t_reached = r.stats.t_reached;
  rec.steps_accepted = r.stats.steps_accepted;
  rec.steps_rejected = r.stats.steps_rejected;
  rec.rhs_calls = r.stats.rhs_calls;
  rec.friction_switches = r.stats.friction_switches;
  rec.metrics = obs.finish(r.stats);
  obs.record_wear(rec.metrics, history);
  obs.record_sensors(rec.metrics, history);
  return rec;
}

}  // namespace

CaseRecord run_case(const CaseSpec& spec, History& history) {
  try {
    return spec.wear_evolution.enabled ? run_wear_evolution(spec, history)
                                       : run_single_case(spec, history);
  } catch (const std::bad_alloc&) {
    throw;  // the environment's failure, not the case's: the runner stops (OutOfMemory)
  } catch (const std::exception& e) {
    // outside the integration (simulate() keeps its own: internal_error with the time reached):
    // building the scene, the observer, the wear evolution's bookkeeping. This case's failure,
    // not the study's; what it recorded so far is dropped.
    CaseRecord rec = start_record(spec);
    rec.finished_utc = rec.started_utc;
    rec.status = RunStatus::internal_error;
    rec.message = std::string("internal error outside the integration, at t = 0 s: ") + e.what();
    history = History{};
    return rec;
  }
}

namespace {

/// Renames a corrupt case file, or a link under a case file's name (the link itself, never its
/// target), to <name>.corrupt (or <name>.corrupt.N, the first free name) in its directory,
/// where no reader takes it for a case file; returns the new path.
fs::path move_aside(const fs::path& path) {
  for (int n = 0;; ++n) {
    fs::path aside = path;
    aside += n == 0 ? ".corrupt" : ".corrupt." + std::to_string(n);
    std::error_code ec;
    if (fs::exists(aside, ec) || ec) {
      if (n < 1000) continue;
    } else if (::rename(path.c_str(), aside.c_str()) == 0) {
      return aside;
    }
    throw std::runtime_error(path.string() + " cannot be moved aside to " + aside.string() + ": " +
                             std::strerror(errno) + "; move it away to rerun its case");
  }
}

/// True when another process holds a write lock on `path`: HDF5 flocks the files it opens,
/// exclusively for writing (h5py in "r+" mode). Such a file is being changed: not damaged, and
/// not to be read, moved or rerun.
bool locked_by_writer(const fs::path& path) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NOFOLLOW | O_NONBLOCK);
  if (fd < 0) return false;
  const bool locked = ::flock(fd, LOCK_SH | LOCK_NB) != 0 && errno == EWOULDBLOCK;
  ::close(fd);
  return locked;
}

/// read_case_record_strict, but a file another process holds open for writing is reported
/// (std::runtime_error: unreadable, never moved aside) before anything reads it.
std::optional<CaseRecord> read_case_unless_locked(const fs::path& path) {
  if (locked_by_writer(path))
    throw std::runtime_error(path.string() +
                             " is locked by another process that has it open for writing (h5py "
                             "in \"r+\" mode?): close it there");
  return read_case_record_strict(path);
}

std::string shell_quote(const std::string& arg) {
  static const char kPlain[] =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789_-./=:,+@%";
  if (!arg.empty() && arg.find_first_not_of(kPlain) == std::string::npos) return arg;
  std::string q = "'";
  for (const char c : arg) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

/// Threads that exist together until released (probe_threads).
struct ThreadProbe {
  std::mutex mutex;
  std::condition_variable released_cv;
  bool released = false;
};

extern "C" void* probe_thread_wait(void* arg) {
  auto* p = static_cast<ThreadProbe*>(arg);
  std::unique_lock lock(p->mutex);
  p->released_cv.wait(lock, [p] { return p->released; });
  return nullptr;
}

/// Starts n - 1 threads (the team OpenMP will start) that wait until all exist, then ends
/// them. libgomp ends the process (exit 1, "Thread creation failed") when it cannot create its
/// threads, so a run checks first. Returns 0 or the error of the first creation that failed;
/// `started`: how many threads existed at once (the caller's included).
int probe_threads(int n, int& started) {
  ThreadProbe probe;
  std::vector<pthread_t> threads;
  threads.reserve(static_cast<std::size_t>(n));
  int err = 0;
  for (int k = 1; k < n && err == 0; ++k) {
    pthread_t t{};
    err = ::pthread_create(&t, nullptr, probe_thread_wait, &probe);
    if (err == 0) threads.push_back(t);
  }
  {
    const std::lock_guard lock(probe.mutex);
    probe.released = true;
  }
  probe.released_cv.notify_all();
  for (const pthread_t t : threads) ::pthread_join(t, nullptr);
  started = static_cast<int>(threads.size()) + 1;
  return err;
}

}  // namespace

std::string resume_command(const Study& study, const RunOptions& opt) {
  std::string cmd = "rodend run " + shell_quote(study.file.string());
  if (study.results_root != "results")
    cmd += " --results-root " + shell_quote(study.results_root.string());
  for (const std::string& o : study.overrides) cmd += " --set " + shell_quote(o);
  if (opt.shard_count > 1)
    cmd += " --shard " + std::to_string(opt.shard_index) + "/" + std::to_string(opt.shard_count);
  if (opt.rerun_failed) cmd += " --rerun-failed";
  return cmd;
}

OutOfMemory::OutOfMemory(long complete, long in_scope, const char* cases_dir,
                         const char* resume) noexcept {
  std::snprintf(text_, sizeof text_,
                "out of memory (a case, or the writing of its results, could not allocate; no "
                "case is recorded as failed for it)\nrodend: stopped: %ld of %ld case(s) "
                "complete in %s; no summary written. Free memory or run fewer threads "
                "(--threads), then resume with: %s",
                complete, in_scope, cases_dir, resume);
}

namespace {

/// The shard of another split (K'/M, M != n) running in `dir`, if any ("" when none): its lock
/// file `.rodend.lock.shard-K'-of-M` is held. Shards of different splits share case files.
std::string other_split_running(const fs::path& dir, int n) {
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec)) {
    const std::string name = e.path().filename().string();
    int k = 0, m = 0;
    char tail = 0;
    if (std::sscanf(name.c_str(), ".rodend.lock.shard-%d-of-%d%c", &k, &m, &tail) != 2 || m == n)
      continue;
    const int fd = ::open(e.path().c_str(), O_RDONLY | O_CLOEXEC | O_NOFOLLOW | O_NONBLOCK);
    if (fd < 0) continue;
    const bool held = ::flock(fd, LOCK_SH | LOCK_NB) != 0 && errno == EWOULDBLOCK;
    ::close(fd);
    if (held) return std::to_string(k) + "/" + std::to_string(m);
  }
  return "";
}

/// Takes the results directory's locks: a full run holds `.rodend.lock` exclusively; a shard
/// K/N holds it shared (the shards of one study run side by side, a full run or a merge waits
/// for them all) and `.rodend.lock.shard-K-of-N` exclusively, and refuses to run beside a shard
/// of another split (checked after its own lock is held: of two starting at once, neither
/// misses the other).
void claim_locks(const Study& study, const RunOptions& opt, RunPlan& plan) {
  const std::string study_lock = std::string(kResultsMarker) + ".lock";
  const std::string file = study.file.string();
  if (opt.shard_count <= 1) {
    plan.lock = ResultsLock::claim(plan.dir, study_lock, file, opt.wait);
    return;
  }
  plan.study_lock = ResultsLock::claim(plan.dir, study_lock, file, opt.wait, /*shared=*/true);
  plan.lock = ResultsLock::claim(plan.dir,
                                 study_lock + ".shard-" + std::to_string(opt.shard_index) + "-of-" +
                                     std::to_string(opt.shard_count),
                                 file, opt.wait);
  // refused even with --wait: two shards of different splits waiting for each other would wait
  // forever, each holding its own lock
  if (const std::string other = other_split_running(plan.dir, opt.shard_count); !other.empty())
    throw std::runtime_error("shard " + other + " of another split runs in " + plan.dir.string() +
                             "; its cases overlap those of shard " +
                             std::to_string(opt.shard_index) + "/" +
                             std::to_string(opt.shard_count) + ": rerun when it has finished");
}

}  // namespace

namespace {

/// The results directories: created, writable, and no directory where a summary or study.json
/// goes; checked before anything runs, so a read-only results folder fails at once, not after
/// the cases. A shard writes its own summary (`rodend merge` assembles the study's).
void prepare_directories(const Study& study, const RunOptions& opt, RunPlan& plan) {
  std::error_code ec;
  fs::create_directories(plan.cases_dir, ec);
  if (ec)
    throw InputError(
        "output",
        "cannot create the results directory " + plan.cases_dir.string() + ": " + ec.message(),
        study.file.string());
  // both directories take files (cases; study.json and the summary)
  for (const fs::path& d : {plan.cases_dir, plan.dir})
    if (::access(d.c_str(), W_OK) != 0)
      throw InputError(
          "output",
          "the results directory " + d.string() + " is not writable (" + std::strerror(errno) + ")",
          study.file.string());
  for (const char* name : {"summary.h5", "summary.csv", "study.json"}) {
    const fs::path f = plan.dir / name;
    if (fs::exists(f, ec) && !fs::is_regular_file(f, ec))
      throw InputError("output",
                       f.string() + " exists and is not a regular file; rodend writes its " + name +
                           " there: move it away",
                       study.file.string());
  }
  plan.summary_dir = opt.shard_count > 1 ? plan.dir / ("shard-" + std::to_string(opt.shard_index) +
                                                       "-of-" + std::to_string(opt.shard_count))
                                         : plan.dir;
  fs::create_directories(plan.summary_dir, ec);
  if (ec)
    throw InputError(
        "output", "cannot create the directory " + plan.summary_dir.string() + ": " + ec.message(),
        study.file.string());
}

/// A summary.csv of another run than summary.h5 (a run stopped between the two renames) is
/// rewritten (the run rewrites both at its end; this keeps the pair consistent until then).
void repair_summary(const RunPlan& plan, const RunOptions& opt) {
  try {
    if (repair_summary_csv(plan.summary_dir) && opt.progress)
      run_message(opt.events, (plan.summary_dir / "summary.csv").string() +
                                  " did not match summary.h5 (a run was stopped between writing "
                                  "the two); rewritten from summary.h5");
  } catch (const std::exception& e) {
    run_message(opt.events, std::string("warning: ") + e.what() +
                                " (the run rewrites both summaries at its end)");
  }
}

/// The stored record of case c (nullopt: no file), read only if no other process writes it;
/// throws CorruptCaseFile for damaged bytes, std::runtime_error when it is another case's.
std::optional<CaseRecord> stored_record(const fs::path& path, const CaseSpec& c) {
  std::optional<CaseRecord> rec = read_case_unless_locked(path);
  if (rec && rec->id != c.id)
    throw std::runtime_error(path.string() + " holds case " + rec->id + ", not " + c.id);
  return rec;
}

/// What is complete already (resume): a case file under its final name is complete once its
/// checksum holds. A corrupt one (damaged bytes: checksum, truncation) is reported, moved aside
/// to <id>.h5.corrupt (never deleted) and its case rerun. One that cannot be read for another
/// reason (another case's, another schema's, not a regular file, no permission) is never
/// touched: it is reported and nothing runs.
void collect_done(const Study& study, const RunOptions& opt, RunPlan& plan) {
  plan.spool = std::make_unique<RecordSpool>(plan.summary_dir, study.cases.size());
  plan.stamps.assign(study.cases.size(), 0);
  std::vector<std::string> unreadable;
  for (std::size_t i = 0; i < study.cases.size(); ++i) {
    const CaseSpec& c = study.cases[i];
    if (!in_shard(c, opt)) continue;
    ++plan.in_scope;
    const fs::path path = plan.cases_dir / (c.id + ".h5");
    std::optional<CaseRecord> rec;
    // taken before the read: a file changed after it is read again before the summary
    const std::uint64_t stamp = case_file_stamp(path);
    try {
      rec = stored_record(path, c);
    } catch (const CorruptCaseFile& e) {
      const fs::path aside = move_aside(path);
      run_message(opt.events,
                  std::string(e.what()) + "; moved to " + aside.string() + ", the case runs again");
      plan.todo.push_back(i);
      continue;
    } catch (const LinkedCaseFile& e) {
      const fs::path aside = move_aside(path);
      run_message(opt.events, std::string(e.what()) + ": moved to " + aside.string() +
                                  " (the link, not its target), the case runs again");
      plan.todo.push_back(i);
      continue;
    } catch (const std::exception& e) {
      unreadable.push_back(e.what());
      continue;
    }
    if (rec && (rec->status == RunStatus::ok || !opt.rerun_failed)) {
      // a file reused from another grid of the study: its row takes this grid's place
      rec->index = c.index;
      rec->coordinates = c.coordinates;
      plan.spool->put(i, *rec);
      plan.stamps[i] = std::max<std::uint64_t>(stamp, 2);
      continue;
    }
    plan.todo.push_back(i);
  }
  if (!unreadable.empty()) {
    std::string m = std::to_string(unreadable.size()) +
                    " case file(s) exist but cannot be read; rodend does not overwrite them. "
                    "Move them away (or delete them) to rerun those cases:";
    for (const std::string& u : unreadable) m += "\n  " + u;
    throw std::runtime_error(m);
  }
}

}  // namespace

RunPlan plan_run(const Study& study, const RunOptions& opt) {
  RunPlan plan;
  plan.dir = study.output_dir;
  plan.cases_dir = plan.dir / "cases";
  plan.resume = resume_command(study, opt);
  claim_locks(study, opt, plan);
  const int stale =
      plan.lock->stale_removed() + (plan.study_lock ? plan.study_lock->stale_removed() : 0);
  if (stale > 0 && opt.progress)
    run_message(opt.events,
                "removed " + std::to_string(stale) + " temporary file(s) left by interrupted runs");
  prepare_directories(study, opt, plan);
  plan.provenance = provenance(study);
  repair_summary(plan, opt);
  collect_done(study, opt, plan);
  order_largest_first(study, plan.todo);  // only the order: ids, files and rows stay the grid's
  // written as every results file is (sweep/results/atomic_file.hpp): a fresh file under an
  // unpredictable temporary name, never through a link, then renamed
  write_text_file_atomically(plan.dir / "study.json", "study file", study.source.dump(2) + "\n",
                             /*durable=*/false);
  // the resolved design, where the analysis finds it (docs/uncertainty.md)
  if (study.design)
    write_text_file_atomically(plan.dir / "design.json", "study file",
                               study.design->to_json(study.design_units).dump(2) + "\n",
                               /*durable=*/false);
  // the profile files the cases read, by name and content (docs/inputs.md)
  if (!study.profiles.empty())
    write_text_file_atomically(plan.dir / "profiles.json", "study file",
                               study.profiles.dump(2) + "\n", /*durable=*/false);
  return plan;
}

CaseRecord run_and_write_case(const Study& study, const RunPlan& plan, std::size_t i) {
  const CaseSpec& spec = study.cases[i];
  History history;
  CaseRecord rec = run_case(spec, history);
  write_case_file(plan.cases_dir / (spec.id + ".h5"), spec, rec, history, plan.provenance);
  note_case_file(plan, i, spec.id);
  return rec;
}

namespace {

/// What stopped the parallel loop early, set by any thread without allocating (but the first
/// error's text); the messages are composed after the loop, on the calling thread.
struct LoopFailure {
  std::atomic<bool> out_of_memory{false}, write_failed{false};
  StopReport* report = nullptr;  ///< its count of complete cases, kept for a second signal
  std::mutex mutex;
  std::size_t first_case = 0;  ///< its study.cases index (resolving its id allocates)
  std::string first_error;

  bool stopping() const { return out_of_memory || write_failed || stop_signal() != 0; }
  void record(std::size_t i, const char* what) noexcept {
    write_failed.store(true);
    try {
      const std::lock_guard lock(mutex);
      if (!first_error.empty()) return;
      first_case = i;
      first_error = what;
    } catch (...) {
      out_of_memory.store(true);  // the text could not be copied: memory ran out
    }
  }
};

/// Runs plan.todo on `threads` OpenMP threads: each prepares HDF5 first (while memory is
/// free), then takes cases until none is left or the run stops.
void run_cases(const Study& study, const RunPlan& plan, int threads, Progress& progress,
               LoopFailure& fail) {
  const long n_todo = static_cast<long>(plan.todo.size());
#pragma omp parallel num_threads(threads)
  {
    try {
      prepare_results_io();
    } catch (const std::bad_alloc&) {
      fail.out_of_memory.store(true);
    }
#pragma omp for schedule(dynamic, 1)
    for (long k = 0; k < n_todo; ++k) {
      // stopping (a signal, memory exhausted, or a results file that could not be written: a
      // full disk fails every case after it): no new cases
      if (fail.stopping()) continue;
      const std::size_t i = plan.todo[static_cast<std::size_t>(k)];
      try {
        const CaseRecord rec = run_and_write_case(study, plan, i);
        plan.spool->put(i, rec);
        if (fail.report) fail.report->complete.fetch_add(1);
        progress.case_done(rec.status != RunStatus::ok);
      } catch (const std::bad_alloc&) {
        fail.out_of_memory.store(true);  // nothing allocated here
      } catch (const std::exception& e) {
        fail.record(i, e.what());
      }
    }
  }
}

/// The team of threads: no more than the cases to run; refused (std::runtime_error naming the
/// count of complete cases and the resume command) when the system cannot start them.
int start_team(const RunOptions& opt, const RunPlan& plan) {
  const int threads = static_cast<int>(
      std::clamp<long>(static_cast<long>(plan.todo.size()), 1, std::max(opt.threads, 1)));
  int started = 0;
  if (const int err = probe_threads(threads, started); err != 0)
    throw std::runtime_error(
        "cannot start " + std::to_string(threads) + " threads (--threads " +
        std::to_string(opt.threads) + "): thread " + std::to_string(started + 1) +
        " could not be created (" + std::strerror(err) +
        "; a memory limit, ulimit -v, or the process limit, ulimit -u)\nrodend: stopped: " +
        std::to_string(plan.in_scope - static_cast<long>(plan.todo.size())) + " of " +
        std::to_string(plan.in_scope) + " case(s) complete in " + plan.cases_dir.string() +
        "; nothing ran. Resume with fewer threads (--threads " + std::to_string(started) +
        " or less): " + plan.resume);
  return threads;
}

}  // namespace

int write_run_summary(const Study& study, const RunPlan& plan) {
  check_case_files(plan);
  try {
    write_summary(plan.summary_dir, study, *plan.spool, plan.provenance);
  } catch (const std::bad_alloc&) {
    throw;
  } catch (const std::exception& e) {  // a full disk, an I/O error: the cases are safe
    throw std::runtime_error(std::string(e.what()) + "; " + std::to_string(plan.spool->size()) +
                             " of " + std::to_string(plan.in_scope) + " cases are complete in " +
                             plan.cases_dir.string() +
                             ", no summary written. Resume with: " + plan.resume);
  }
  return plan.spool->failed() > 0 ? 1 : 0;
}

int run_study(const Study& study, const RunOptions& opt) {
  RunPlan plan = plan_run(study, opt);
  const auto complete = [&plan] { return static_cast<long>(plan.spool->size()); };
  try {
    prepare_results_io();  // the library, on this thread, before any other thread uses it
    const int threads = start_team(opt, plan);
    StopReport report;  // what a second signal prints
    report.complete = complete();
    report.in_scope = plan.in_scope;
    report.tail =
        " in " + plan.cases_dir.string() +
        "; the cases in flight are not written, no summary written. Resume with: " + plan.resume +
        "\n";
    // a report for a second signal only where the notices go to stderr (`rodend run`); Python's
    // run_study, whose messages go to its logging, keeps the default action for the second
    const bool quiet = static_cast<bool>(opt.events.message);
    const StopSignalScope stop_signals(StopSignalScope::Kind::batch, quiet,
                                       quiet ? nullptr : &report);
    Progress progress(opt.progress, plan.in_scope,
                      plan.in_scope - static_cast<long>(plan.todo.size()), opt.events);
    LoopFailure fail;
    fail.report = &report;
    run_cases(study, plan, threads, progress, fail);
    if (fail.out_of_memory)
      throw OutOfMemory(complete(), plan.in_scope, plan.cases_dir.c_str(), plan.resume.c_str());
    if (fail.write_failed)
      throw std::runtime_error("case " + study.cases[fail.first_case].id + ": " + fail.first_error +
                               "\nrodend: stopped: " + std::to_string(complete()) + " of " +
                               std::to_string(plan.in_scope) + " case(s) complete in " +
                               plan.cases_dir.string() +
                               "; no summary written. Resume with: " + plan.resume);
    if (const int sig = stop_signal(); sig != 0) {
      progress.break_line();
      run_message(opt.events, std::string("stopped by ") + stop_signal_name(sig) + ": " +
                                  std::to_string(complete()) + " of " +
                                  std::to_string(plan.in_scope) + " case(s) complete in " +
                                  plan.cases_dir.string() +
                                  "; no summary written. Resume with: " + plan.resume);
      return 128 + sig;
    }
    return write_run_summary(study, plan);
  } catch (const OutOfMemory&) {
    throw;
  } catch (const std::bad_alloc&) {  // on this thread: the summary, the messages
    throw OutOfMemory(complete(), plan.in_scope, plan.cases_dir.c_str(), plan.resume.c_str());
  }
}

namespace {

/// The shard count, when the shard summaries present in `dir` agree on one (to name missing
/// shards); 0 otherwise.
int shard_count_in(const fs::path& dir) {
  int shards = 0;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec)) {
    int k = 0, n = 0;
    char tail = 0;
    const std::string name = e.path().filename().string();
    if (std::sscanf(name.c_str(), "shard-%d-of-%d%c", &k, &n, &tail) == 2 && n > 0)
      shards = (shards == 0 || shards == n) ? n : -1;
  }
  return shards < 0 ? 0 : shards;
}

/// The case files of a merge: the records found (into the spool), and those that are missing,
/// corrupt or unreadable.
struct MergeScan {
  std::vector<std::pair<long, std::string>> missing;  // case index, case id
  std::vector<std::string> unreadable, corrupt, linked;
};

MergeScan scan_case_files(const Study& study, const fs::path& cases_dir, RecordSpool& rows) {
  MergeScan scan;
  std::size_t slot = 0;
  for (const CaseSpec& c : study.cases) {
    const std::size_t i = slot++;
    std::optional<CaseRecord> rec;
    try {
      rec = read_case_unless_locked(cases_dir / (c.id + ".h5"));
    } catch (const CorruptCaseFile& e) {
      scan.corrupt.push_back(e.what());
      continue;
    } catch (const LinkedCaseFile& e) {
      scan.linked.push_back(e.what());
      continue;
    } catch (const std::exception& e) {
      scan.unreadable.push_back(e.what());
      continue;
    }
    if (rec) {
      rec->index = c.index;
      rec->coordinates = c.coordinates;
      rows.put(i, *rec);
    } else {
      scan.missing.emplace_back(c.index, c.id);
    }
  }
  return scan;
}

/// The profiles the study reads whose content differs from that recorded in the results
/// folder's profiles.json (written by the run): one line each, "" when none (or no record).
std::string changed_profiles(const Study& study, const fs::path& dir) {
  const fs::path recorded_file = dir / "profiles.json";
  std::error_code ec;
  if (!fs::is_regular_file(fs::symlink_status(recorded_file, ec)) ||
      fs::file_size(recorded_file, ec) > (16u << 20))
    return "";
  Json recorded;
  try {
    std::ifstream in(recorded_file, std::ios::binary);
    recorded = Json::parse(in);
  } catch (const std::exception&) {
    return "";  // not the run's: nothing to say from it
  }
  std::string out;
  for (const Json& now : study.profiles)
    for (const Json& then : recorded.is_array() ? recorded : Json::array())
      if (then.is_object() && then.value("file", "") == now.value("file", "") &&
          then.value("column", "") == now.value("column", "") &&
          then.value("content_fnv1a64", "") != now.value("content_fnv1a64", ""))
        out += "  " + now.value("file", "") + " (column '" + now.value("column", "") +
               "'): content fnv1a64 " + then.value("content_fnv1a64", "") +
               " when the run read it, " + now.value("content_fnv1a64", "") + " now\n";
  return out;
}

/// The case files that are links, corrupt, or cannot be read: reported; true when any.
bool report_unusable(const Study& study, const MergeScan& scan, std::ostream& report) {
  if (!scan.linked.empty()) {
    report << "rodend: " << scan.linked.size()
           << " case file(s) are symbolic links; no summary written. This moves the links aside "
              "(never their targets) and reruns those cases: "
           << resume_command(study, RunOptions{}) << "\n";
    for (const std::string& u : scan.linked) report << "  " << u << "\n";
  }
  if (!scan.corrupt.empty()) {
    report << "rodend: " << scan.corrupt.size()
           << " case file(s) are corrupt; no summary written. `rodend run` on the study moves "
              "them aside and reruns those cases:\n";
    for (const std::string& u : scan.corrupt) report << "  " << u << "\n";
  }
  if (!scan.unreadable.empty()) {
    report << "rodend: " << scan.unreadable.size()
           << " case file(s) exist but cannot be read; no summary written. Move them away and "
              "rerun those cases (rodend run resumes):\n";
    for (const std::string& u : scan.unreadable) report << "  " << u << "\n";
  }
  return !scan.corrupt.empty() || !scan.unreadable.empty() || !scan.linked.empty();
}

/// Reports why no summary can be merged; false when there is no such reason.
bool report_incomplete(const Study& study, const MergeScan& scan, const fs::path& cases_dir,
                       int shards, std::ostream& report) {
  if (report_unusable(study, scan, report)) return true;
  if (scan.missing.empty()) return false;
  if (const std::string changed = changed_profiles(study, cases_dir.parent_path());
      !changed.empty())
    report << "rodend: profile file(s) changed since the run read them; a profile's content is "
              "part of its cases' ids, so the cases that read them are new cases, computed by: "
           << resume_command(study, RunOptions{}) << "\n"
           << changed;
  report << "rodend: " << scan.missing.size() << " of " << study.cases.size()
         << " cases have no complete file in " << cases_dir.string()
         << "; no summary written. Missing (case index, case id"
         << (shards > 0 ? ", shard K/N" : "") << "):\n";
  for (const auto& [index, id] : scan.missing) {
    report << "  " << index << "\t" << id;
    if (shards > 0) report << "\t" << (index % shards) + 1 << "/" << shards;
    report << "\n";
  }
  return true;
}

}  // namespace

int merge_study(const Study& study, std::ostream& report) {
  const fs::path dir = study.output_dir;
  const fs::path cases_dir = dir / "cases";
  if (!fs::is_directory(dir))
    throw InputError("output", "no results directory " + dir.string() + " to merge",
                     study.file.string());
  const auto lock =
      ResultsLock::claim(dir, std::string(kResultsMarker) + ".lock", study.file.string(), false);
  RecordSpool rows(dir, study.cases.size());
  const int shards = shard_count_in(dir);
  if (repair_summary_csv(dir))
    report << "rodend: " << (dir / "summary.csv").string()
           << " did not match summary.h5 (a run was stopped between writing the two); rewritten "
              "from summary.h5\n";
  const MergeScan scan = scan_case_files(study, cases_dir, rows);
  if (report_incomplete(study, scan, cases_dir, shards, report)) return 1;
  const std::size_t failed = rows.failed(), merged = rows.size();
  write_summary(dir, study, rows, provenance(study));
  report << "rodend: merged " << merged << " cases (" << failed << " failed) into "
         << (dir / "summary.h5").string() << " and summary.csv\n";
  return 0;
}

}  // namespace rodend
