// Distributed runs over MPI; see mpi_runner.hpp. This is the only file that calls MPI.
//
// Protocol (MPI_COMM_WORLD, ints only):
//   worker thread t -> rank 0, tag kTagRequest: {cases ok, cases failed since its last request,
//                     t}, i.e. "give me a case" (12 bytes);
//   rank 0 -> that rank, tag kTagWork + t: {a case index into Study::cases, or -1: no more work;
//                     the cases still to hand out after it} (8 bytes).
// Each thread receives its replies on a tag of its own, so it posts the receive, sends the
// request and waits for the reply without holding g_mpi (MPI_THREAD_SERIALIZED: one MPI call at
// a time per rank). While many cases are left, a worker thread asks for its next case as it
// starts one (one request ahead), so the manager's latency is hidden behind the computation;
// the last 2 x (computing threads of the job) cases are asked for one at a time, so that no
// thread holds a case while another idles at the end. A rank enters the final barrier after
// each of its threads got -1; rank 0's
// manager serves requests until that barrier completes, so when it does every case handed out
// has its file under its final name.
//
// Waiting: Open MPI's blocking calls spin a core at 100%. Everything that may wait (a worker's
// reply, the manager's idle time, the end barrier, the broadcasts while rank 0 scans or
// summarises) polls with MPI_Test/MPI_Iprobe and short sleeps instead, so idle ranks and the
// manager leave the cores to the computing threads, also on an oversubscribed node.
//
// Stopping: SIGINT or SIGTERM to a rank (mpirun forwards SIGTERM to every rank when it is
// interrupted or terminated, then sends SIGKILL a second later; Slurm signals every task) ends
// that rank within milliseconds: the cases in flight are abandoned (their files exist only
// under hidden temporary names, removed by the next run), rank 0 prints the count of complete
// cases and the resume command, and each rank exits 128 + the signal's number.
#include "sweep/mpi_runner.hpp"

#include <cstdlib>

#ifdef RODEND_HAVE_MPI

#include <mpi.h>
#include <omp.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <functional>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <utility>

#include "sweep/clock.hpp"
#include "sweep/record_bytes.hpp"
#include "sweep/results_dir.hpp"
#include "sweep/stop_signals.hpp"

namespace rodend::mpi {
namespace fs = std::filesystem;

namespace {

constexpr int kTagRequest = 1;
constexpr int kTagWork = 16;                     // + the asking thread's number
constexpr int kNone = -1, kOk = 0, kFailed = 1;  // request payload
constexpr int kNoMoreWork = -1;                  // reply payload
constexpr int kManagerIdlePollUs = 1000;         // the manager's sleep when no request waits
constexpr int kReplyPollUs = 50;                 // a worker's sleep while its reply is due

/// Serialises every MPI call made while threads run (MPI_THREAD_SERIALIZED).
std::mutex g_mpi;
/// The library gave MPI_THREAD_SERIALIZED or better; without it, one thread per rank.
bool g_threads_ok = false;

void sleep_us(int us) {
  std::this_thread::sleep_for(std::chrono::microseconds(us));
}

/// The cost of handing out cases (printed by rank 0 with RODEND_MPI_STATS=1; bench/README.md).
struct DispatchStats {
  std::atomic<long long> served{0}, serve_ns{0}, serve_cpu_ns{0};  // rank 0's manager
  long long manager_cpu_ns = 0;  // the manager thread's CPU time, idle polling included
  long long idle_polls = 0;
  std::atomic<long long> asks{0}, wait_ns{0};  // this rank's threads, waiting for their replies
  std::atomic<long long> bytes{0};             // request and reply bytes through the manager
};
DispatchStats g_stats;

/// A rank being stopped by a signal (stop_signal(), sweep/stop_signals.hpp): whatever fails on
/// its threads now (a case file whose temporary was removed under it) is part of the stop, not
/// an error; RankWatch ends the rank.
void defer_to_stop() {
  if (stop_signal() == 0) return;
  for (;;) sleep_us(1000000);
}

/// Completes `req` by polling (see the file comment).
void wait_polled(MPI_Request& req, int poll_us = 1000) {
  for (;;) {
    int done = 0;
    {
      std::lock_guard lock(g_mpi);
      MPI_Test(&req, &done, MPI_STATUS_IGNORE);
    }
    if (done) return;
    sleep_us(poll_us);
  }
}

void bcast_int_polled(int& value) {
  MPI_Request req;
  {
    std::lock_guard lock(g_mpi);
    MPI_Ibcast(&value, 1, MPI_INT, 0, MPI_COMM_WORLD, &req);
  }
  wait_polled(req);
}

/// Ends the whole job: the message on stderr, then MPI_Abort. Callable from any thread.
[[noreturn]] void fatal(int rank, const std::string& what) {
  defer_to_stop();
  std::lock_guard lock(g_mpi);  // no other thread of this rank is inside MPI
  std::fprintf(stderr, "rodend: error: rank %d on %s: %s\nrodend: aborting the MPI job\n", rank,
               host_name().c_str(), what.c_str());
  std::fflush(stderr);
  MPI_Abort(MPI_COMM_WORLD, 2);
  std::_Exit(2);  // not reached
}

/// fatal() for memory that ran out: a fixed message, nothing allocated (the job is resumed by
/// rerunning the same command: no case was recorded as failed for it).
[[noreturn]] void fatal_out_of_memory(int rank) {
  defer_to_stop();
  std::lock_guard lock(g_mpi);
  std::fprintf(stderr,
               "rodend: error: rank %d: out of memory (no case is recorded as failed for it); "
               "free memory or run fewer threads, then rerun the same command to resume\n"
               "rodend: aborting the MPI job\n",
               rank);
  std::fflush(stderr);
  MPI_Abort(MPI_COMM_WORLD, 2);
  std::_Exit(2);  // not reached
}

/// Rank 0's queue of case indices, shared by the manager and rank 0's computing threads; counts
/// the cases handed to each rank.
class WorkQueue {
 public:
  WorkQueue(const std::vector<std::size_t>& todo, int ranks) : todo_(todo), given_(ranks, 0) {}
  int take(int rank, int* remaining = nullptr) {
    std::lock_guard lock(mutex_);
    const bool empty = next_ >= todo_.size();
    if (!empty) ++given_[static_cast<std::size_t>(rank)];
    const int i = empty ? kNoMoreWork : static_cast<int>(todo_[next_++]);
    if (remaining != nullptr) *remaining = static_cast<int>(todo_.size() - next_);
    return i;
  }
  std::vector<long> given() {
    std::lock_guard lock(mutex_);
    return given_;
  }

 private:
  const std::vector<std::size_t>& todo_;
  std::size_t next_ = 0;
  std::vector<long> given_;
  std::mutex mutex_;
};

/// What rank 0's manager and computing threads share.
struct Rank0 {
  const Study& study;
  const RunPlan& plan;
  WorkQueue queue;
  Progress progress;
};

/// Puts the records a worker sent (sweep/record_bytes.hpp) into the summary's spool, their
/// index, scene and coordinates from rank 0's own copy of the study; returns the sender's
/// thread. A malformed message, or a disk that cannot take the spool, ends the job.
int take_records(std::string_view in, Rank0& r0) {
  int thread = 0;
  try {
    if (in.size() < sizeof thread) throw std::runtime_error("a request message is truncated");
    std::memcpy(&thread, in.data(), sizeof thread);
    in.remove_prefix(sizeof thread);
    while (!in.empty()) {
      CaseRecord rec;
      const std::size_t i = unpack_record(in, rec);
      const CaseSpec& c = r0.study.cases.at(i);
      if (rec.id != c.id) throw std::runtime_error("a record of case " + rec.id + " for " + c.id);
      rec.index = c.index;
      rec.scene = c.scene;
      rec.coordinates = c.coordinates;
      r0.plan.spool->put(i, rec);
      note_case_file(r0.plan, i, c.id);  // written by its rank before it reported
      r0.progress.case_done(rec.status != RunStatus::ok);
    }
  } catch (const std::bad_alloc&) {
    fatal_out_of_memory(0);
  } catch (const std::exception& e) {
    fatal(0, std::string("manager: ") + e.what());
  }
  return thread;
}

/// The manager's answer to the request `st` announced: takes its records, sends the next case.
void serve(const MPI_Status& st, Rank0& r0) {
  const long long t0 = clock_ns(), c0 = clock_ns(CLOCK_THREAD_CPUTIME_ID);
  int bytes = 0;
  std::string request;
  {
    std::lock_guard lock(g_mpi);
    MPI_Get_count(&st, MPI_BYTE, &bytes);
    request.resize(static_cast<std::size_t>(bytes));
    MPI_Recv(request.data(), bytes, MPI_BYTE, st.MPI_SOURCE, kTagRequest, MPI_COMM_WORLD,
             MPI_STATUS_IGNORE);
  }
  const int thread = take_records(request, r0);
  int reply[2] = {kNoMoreWork, 0};
  reply[0] = r0.queue.take(st.MPI_SOURCE, &reply[1]);
  {
    std::lock_guard lock(g_mpi);
    MPI_Send(reply, 2, MPI_INT, st.MPI_SOURCE, kTagWork + thread, MPI_COMM_WORLD);
  }
  g_stats.serve_cpu_ns += clock_ns(CLOCK_THREAD_CPUTIME_ID) - c0;
  g_stats.serve_ns += clock_ns() - t0;
  g_stats.bytes += bytes + static_cast<long long>(sizeof reply);
  ++g_stats.served;
}

/// Rank 0's manager: answers requests until every other rank has entered the end barrier.
void manage(Rank0& r0) {
  const long long c0 = clock_ns(CLOCK_THREAD_CPUTIME_ID);
  MPI_Request barrier;
  {
    std::lock_guard lock(g_mpi);
    MPI_Ibarrier(MPI_COMM_WORLD, &barrier);
  }
  for (long idle = 0;; ++idle) {
    int pending = 0, done = 0;
    MPI_Status st;
    {
      std::lock_guard lock(g_mpi);
      MPI_Iprobe(MPI_ANY_SOURCE, kTagRequest, MPI_COMM_WORLD, &pending, &st);
      // the barrier completes only at the end: tested on every 16th idle poll (each test runs
      // the collective's progress engine)
      if (!pending && idle % 16 == 0) MPI_Test(&barrier, &done, MPI_STATUS_IGNORE);
    }
    if (pending) {
      serve(st, r0);
      continue;  // drain bursts (every thread asks at the start) without sleeping
    }
    if (done) break;
    ++g_stats.idle_polls;
    sleep_us(kManagerIdlePollUs);
  }
  g_stats.manager_cpu_ns = clock_ns(CLOCK_THREAD_CPUTIME_ID) - c0;
}

/// A worker thread's requests to rank 0: each carries the records of the cases it finished since
/// its last request (sweep/record_bytes.hpp) and receives {next case index or kNoMoreWork,
/// cases left} on the thread's own tag.
class Asker {
 public:
  explicit Asker(int thread) : thread_(thread) { restart(); }
  void finished(std::size_t slot, const CaseRecord& rec) {
    pack_record(slot, rec, records_);
    ++owed_;
  }
  bool owes_report() const { return owed_ > 0; }
  void post() {
    sending_.swap(records_);
    restart();
    std::lock_guard lock(g_mpi);
    MPI_Irecv(reply_, 2, MPI_INT, 0, kTagWork + thread_, MPI_COMM_WORLD, &recv_);
    MPI_Isend(sending_.data(), static_cast<int>(sending_.size()), MPI_BYTE, 0, kTagRequest,
              MPI_COMM_WORLD, &send_);
  }
  /// Waits for the reply to the request posted; returns {case index, cases left}.
  std::pair<int, int> reply() {
    const long long t0 = clock_ns();
    wait_polled(recv_, kReplyPollUs);
    wait_polled(send_, kReplyPollUs);
    g_stats.wait_ns += clock_ns() - t0;
    ++g_stats.asks;
    return {reply_[0], reply_[1]};
  }

 private:
  void restart() {
    records_.assign(sizeof thread_, '\0');
    std::memcpy(records_.data(), &thread_, sizeof thread_);
    owed_ = 0;
  }
  const int thread_;
  std::string records_, sending_;  // the next request's bytes; the one in flight
  int owed_ = 0;
  int reply_[2] = {kNoMoreWork, 0};
  MPI_Request recv_ = MPI_REQUEST_NULL, send_ = MPI_REQUEST_NULL;
};

/// Runs case `i` and writes its file; returns its record. Memory that runs out or a file that
/// cannot be written ends the job (fatal).
CaseRecord run_one(int rank, const Study& study, const RunPlan& plan, int i) {
  try {
    return run_and_write_case(study, plan, static_cast<std::size_t>(i));
  } catch (const std::bad_alloc&) {
    fatal_out_of_memory(rank);
  } catch (const std::exception& e) {
    fatal(rank, "case " + study.cases[static_cast<std::size_t>(i)].id + ": " + e.what());
  }
}

void prepare_io(int rank) {
  try {
    prepare_results_io();  // while memory is free (sweep/results.hpp)
  } catch (const std::bad_alloc&) {
    fatal_out_of_memory(rank);
  }
}

/// A worker thread: asks rank 0 for a case (one request ahead while more than `ahead_above`
/// cases are left), runs it, writes its file, and so on until none is left.
void work_remote(int rank, const Study& study, const RunPlan& plan, int ahead_above) {
  prepare_io(rank);
  Asker asker(omp_get_thread_num());
  asker.post();
  for (;;) {
    const auto [i, left] = asker.reply();
    if (i < 0) break;
    const bool ahead = left > ahead_above;
    if (ahead) asker.post();
    asker.finished(static_cast<std::size_t>(i), run_one(rank, study, plan, i));
    if (!ahead) asker.post();
  }
  if (asker.owes_report()) {  // the last case's record
    asker.post();
    asker.reply();
  }
}

/// One of rank 0's computing threads: takes cases from the queue directly.
void work_local(Rank0& r0) {
  prepare_io(0);
  for (int i = r0.queue.take(0); i >= 0; i = r0.queue.take(0)) {
    const CaseRecord rec = run_one(0, r0.study, r0.plan, i);
    try {
      r0.plan.spool->put(static_cast<std::size_t>(i), rec);
    } catch (const std::exception& e) {
      fatal(0, e.what());
    }
    r0.progress.case_done(rec.status != RunStatus::ok);
  }
}

/// Waits until the case file another rank wrote shows on rank 0. On a network file system a
/// file renamed on one node may take a few seconds to show on another (cached directory
/// entries): retries for up to 60 s, listing the directory to revalidate it, before giving up.
void await_visible(const fs::path& cases_dir, const CaseSpec& c) {
  const fs::path path = cases_dir / (c.id + ".h5");
  const auto t0 = std::chrono::steady_clock::now();
  for (;;) {
    struct stat st {};
    if (::lstat(path.c_str(), &st) == 0) return;
    if (std::chrono::steady_clock::now() - t0 > std::chrono::seconds(60))
      throw std::runtime_error("case " + c.id + " was run but " + path.string() +
                               " does not show on rank 0");
    std::error_code ec;
    for (fs::directory_iterator it(cases_dir, ec), end; !ec && it != end; it.increment(ec)) {
    }
    sleep_us(500000);
  }
}

/// What rank 0 prints when a signal stops the run (set once it knows the study); nothing on the
/// other ranks.
using StopReport = std::function<void(int signal)>;

/// Watches over a rank for the whole run, on a thread of its own:
/// - a stop signal (SIGINT, SIGTERM) ends the rank at once with exit code 128 + the signal's
///   number, after rank 0's report (see the file comment);
/// - the launcher's death. A SIGKILL to mpirun (or to the orted of a node) does not reach the
///   ranks, each in a process group of its own, and Open MPI does not stop them either. The
///   rank's parent is the launcher (mpirun, orted or slurmstepd); when it changes, the launcher
///   is gone and the rank exits at once (exit 3; files being written stay under their hidden
///   temporary names: resume reruns those cases).
class RankWatch {
 public:
  RankWatch() : parent_(::getppid()) {
    thread_ = std::thread([this] { watch(); });
  }
  ~RankWatch() {
    done_.store(true);
    wake_stop_signal_waiters();
    thread_.join();
  }
  RankWatch(const RankWatch&) = delete;
  RankWatch& operator=(const RankWatch&) = delete;
  void arm(StopReport report) {
    std::lock_guard lock(mutex_);
    report_ = std::move(report);
  }

 private:
  void watch() {
    for (;;) {
      if (const int sig = wait_for_stop_signal(std::chrono::milliseconds(200)); sig != 0) stop(sig);
      if (done_.load()) return;
      if (::getppid() != parent_) {
        std::fprintf(stderr, "rodend: the MPI launcher is gone; this rank stops\n");
        std::fflush(stderr);
        std::_Exit(3);
      }
    }
  }
  [[noreturn]] void stop(int sig) {
    {
      std::lock_guard lock(mutex_);
      if (report_) report_(sig);
    }
    std::fflush(stderr);
    std::_Exit(128 + sig);
  }
  const pid_t parent_;
  /// SIGINT and SIGTERM recorded (the first) and waking watch(), for the rank's whole run
  const StopSignalScope signals_{StopSignalScope::Kind::rank};
  std::atomic<bool> done_{false};
  std::mutex mutex_;
  StopReport report_;
  std::thread thread_;  // last: started once the members above exist
};

/// Takes the stop report back from a RankWatch when it goes out of scope.
struct Disarm {
  RankWatch& watch;
  ~Disarm() { watch.arm(nullptr); }
};

/// The case files of plan.todo as they were when the run started (their inode, 0 for none): a
/// file renamed into place since then is a case this run completed, one still there from
/// before (a failed case kept for --rerun-failed) is not.
std::vector<ino_t> inodes_of(const Study& study, const RunPlan& plan) {
  std::vector<ino_t> inodes;
  inodes.reserve(plan.todo.size());
  for (const std::size_t i : plan.todo) {
    struct stat st {};
    const fs::path f = plan.cases_dir / (study.cases[i].id + ".h5");
    inodes.push_back(::lstat(f.c_str(), &st) == 0 && S_ISREG(st.st_mode) ? st.st_ino : 0);
  }
  return inodes;
}

/// Removes the temporary files this process was writing in `dir` (the cases abandoned by a
/// stop: `.<name>.tmp.<host>.<pid>.<n>`, sweep/results/atomic_file.cpp), so that none is left
/// behind even where the next run cannot tell that their writer is gone (another node).
void remove_own_temporaries(const fs::path& dir) {
  const std::string mine = ".tmp." + host_name() + "." + std::to_string(::getpid()) + ".";
  std::error_code ec;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    std::error_code ignored;
    if (name.front() == '.' && name.find(mine) != std::string::npos)
      fs::remove(it->path(), ignored);
  }
}

/// Rank 0's report of a stop: the complete cases counted from the files under their final
/// names, whichever rank wrote them; the resume command.
void report_stop(int sig, const Study& study, const RunPlan& plan, const std::vector<ino_t>& before,
                 int ranks) {
  const std::vector<ino_t> now = inodes_of(study, plan);
  long complete = plan.in_scope - static_cast<long>(plan.todo.size());
  for (std::size_t k = 0; k < now.size(); ++k) complete += now[k] != 0 && now[k] != before[k];
  std::fprintf(stderr,
               "\nrodend: stopped by %s: %ld of %ld case(s) complete in %s; the cases in flight "
               "were abandoned (the resume reruns them); no summary written. Resume with: "
               "mpirun -np %d %s (the launcher's other options as before; any rank or thread "
               "count gives the same results)\n",
               stop_signal_name(sig), complete, plan.in_scope, plan.cases_dir.c_str(), ranks,
               plan.resume.c_str());
}

/// A fingerprint of a loaded study: every rank must run the same cases into the same place.
std::string fingerprint(const Study& s) {
  std::string text = fs::absolute(s.output_dir).lexically_normal().string();
  for (const CaseSpec& c : s.cases) {
    text += '\n';
    text += c.id;
  }
  return fnv1a64_hex(text);
}

/// Step 1: every rank loads the study and they check that they agree on it (the same file on
/// every node). nullopt, after one message, when any rank could not.
std::optional<Study> load_on_every_rank(int rank, const fs::path& study_file,
                                        const fs::path& results_root, const RunOptions& opt) {
  std::optional<Study> study;
  std::string error;
  try {
    study = load_study(study_file, results_root, opt.overrides);
  } catch (const std::exception& e) {
    error = e.what();
  }
  char print0[17] = {};  // rank 0's fingerprint, empty when rank 0 could not load the study
  if (study) std::strncpy(print0, fingerprint(*study).c_str(), 16);
  MPI_Bcast(print0, 17, MPI_CHAR, 0, MPI_COMM_WORLD);
  if (error.empty() && fingerprint(*study) != print0 && print0[0] != 0)
    error = "rank " + std::to_string(rank) + " on " + host_name() + " resolves " +
            study_file.string() + " to other cases or another results directory than rank 0";
  // rank 0 reports its own problem; the others report only a problem rank 0 does not have
  if (!error.empty() && (rank == 0 || print0[0] != 0))
    std::fprintf(stderr, "rodend: error: %s\n", error.c_str());
  int ok = error.empty() ? 1 : 0, all_ok = 0;
  MPI_Allreduce(&ok, &all_ok, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
  if (!all_ok) return std::nullopt;
  return study;
}

/// Step 2: rank 0 decides what to run from the case files present, exactly as run_study does;
/// the other ranks take what a worker needs of the plan. Returns 0, or 2 on every rank.
int plan_on_rank0(int rank, const Study& study, const RunOptions& opt, RunPlan& plan) {
  int status = 0;
  if (rank == 0) {
    try {
      plan = plan_run(study, opt);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "rodend: error: %s\n", e.what());
      status = 2;
    }
  }
  bcast_int_polled(status);
  if (status != 0 || rank == 0) return status;
  plan.dir = study.output_dir;
  plan.cases_dir = plan.dir / "cases";
  plan.provenance = provenance(study);  // this rank's host goes into the files it writes
  return 0;
}

/// Step 3: rank 0 manages (thread 0) and computes (threads 1..T); the others compute. Returns
/// the cases run by each rank (on rank 0).
std::vector<long> run_on_every_rank(const Session& session, const Study& study, const RunPlan& plan,
                                    int threads, bool progress_on) {
  if (session.rank() != 0) {
#pragma omp parallel num_threads(threads)
    work_remote(session.rank(), study, plan, 2 * threads * session.size());
    MPI_Request barrier;
    {
      std::lock_guard lock(g_mpi);
      MPI_Ibarrier(MPI_COMM_WORLD, &barrier);
    }
    wait_polled(barrier);
    return {};
  }
  Rank0 r0{
      study, plan, WorkQueue(plan.todo, session.size()),
      Progress(progress_on, plan.in_scope, plan.in_scope - static_cast<long>(plan.todo.size()))};
#pragma omp parallel num_threads(threads + 1)
  {
    if (omp_get_thread_num() == 0)
      manage(r0);
    else
      work_local(r0);
  }
  return r0.queue.given();
}

/// Step 4: rank 0 writes the summary from the records it holds, once every new case file shows
/// on it; every rank returns the exit code.
int summarise(int rank, const Study& study, RunPlan& plan) {
  int rc = 0;
  if (rank == 0) {
    try {
      for (const std::size_t i : plan.todo) await_visible(plan.cases_dir, study.cases[i]);
      rc = write_run_summary(study, plan);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "rodend: error: %s\n", e.what());
      rc = 2;
    }
  }
  bcast_int_polled(rc);
  return rc;
}

/// Rank 0's closing lines: the cases per rank and, with RODEND_MPI_STATS=1, the dispatch
/// costs (the workers' waits summed over the ranks: a collective, so every rank calls this).
void print_closing(const Session& session, const std::vector<long>& given, bool progress) {
  long long mine[2] = {g_stats.asks.load(), g_stats.wait_ns.load()}, all[2] = {0, 0};
  MPI_Reduce(mine, all, 2, MPI_LONG_LONG, MPI_SUM, 0, MPI_COMM_WORLD);
  if (session.rank() != 0) return;
  if (progress) {
    std::string per_rank;
    for (const long n : given) per_rank += " " + std::to_string(n);
    std::fprintf(stderr, "rodend: %d MPI ranks, cases run by rank 0..%d:%s\n", session.size(),
                 session.size() - 1, per_rank.c_str());
  }
  if (std::getenv("RODEND_MPI_STATS") == nullptr) return;
  const double served = std::max(1.0, static_cast<double>(g_stats.served.load()));
  const double asks = std::max(1.0, static_cast<double>(all[0]));
  std::fprintf(stderr,
               "rodend: MPI dispatch: %lld requests served, %.1f us wall and %.1f us CPU of the "
               "manager each, %.0f bytes each (request with its records, and reply); manager "
               "thread %.3f s CPU in all, %lld idle polls; a worker waited %.1f us per request\n",
               g_stats.served.load(), 1e-3 * static_cast<double>(g_stats.serve_ns) / served,
               1e-3 * static_cast<double>(g_stats.serve_cpu_ns) / served,
               static_cast<double>(g_stats.bytes) / served,
               1e-9 * static_cast<double>(g_stats.manager_cpu_ns), g_stats.idle_polls,
               1e-3 * static_cast<double>(all[1]) / asks);
}

/// On one node, Open MPI's default point-to-point layer probes UCX first, which costs about
/// 0.2 s of MPI_Init on the development VM (0.30 s against 0.10-0.13 s with ob1); ob1 over
/// shared memory is what a one-node job uses for rodend's few small messages anyway. Chosen
/// only when every rank is on this node and the user did not choose (--mca pml, OMPI_MCA_pml).
void prefer_ob1_on_one_node() {
  const char* size = std::getenv("OMPI_COMM_WORLD_SIZE");
  const char* local = std::getenv("OMPI_COMM_WORLD_LOCAL_SIZE");
  if (size != nullptr && local != nullptr && std::strcmp(size, local) == 0)
    ::setenv("OMPI_MCA_pml", "ob1", /*overwrite=*/0);
}

}  // namespace

bool built_in() {
  return true;
}

bool launched() {
  for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK", "PMI_SIZE"})
    if (std::getenv(v) != nullptr) return true;
  return false;
}

Session::Session(bool wanted) {
  if (!wanted) return;
  prefer_ob1_on_one_node();
  int provided = MPI_THREAD_SINGLE;
  MPI_Init_thread(nullptr, nullptr, MPI_THREAD_SERIALIZED, &provided);  // errors are fatal
  g_threads_ok = provided >= MPI_THREAD_SERIALIZED;
  active_ = true;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &size_);
}

Session::~Session() {
  if (active_) MPI_Finalize();
}

int run_study_mpi(const Session& session, const fs::path& study_file, const fs::path& results_root,
                  RunOptions opt) {
  const int rank = session.rank();
  RankWatch watch;
  const std::optional<Study> study = load_on_every_rank(rank, study_file, results_root, opt);
  if (!study) return 2;
  if (!g_threads_ok && opt.threads > 1) {
    if (rank == 0)
      std::fprintf(stderr,
                   "rodend: warning: the MPI library does not allow calls from several "
                   "threads; running one case at a time per rank\n");
    opt.threads = 1;
  }
  RunPlan plan;
  const Disarm disarm{watch};  // first to go: the reports below refer to `study` and `plan`
  if (rank == 0)               // a stop while rank 0 plans: nothing ran yet
    watch.arm([&](int sig) {
      std::fprintf(stderr,
                   "\nrodend: stopped by %s before any case ran. Resume with: mpirun -np %d %s\n",
                   stop_signal_name(sig), session.size(), resume_command(*study, opt).c_str());
    });
  if (const int status = plan_on_rank0(rank, *study, opt, plan); status != 0) return status;
  watch.arm([&, before = rank == 0 ? inodes_of(*study, plan) : std::vector<ino_t>{}](int sig) {
    remove_own_temporaries(plan.cases_dir);
    if (rank != 0) return;
    remove_own_temporaries(plan.summary_dir);
    report_stop(sig, *study, plan, before, session.size());
  });
  const std::vector<long> given =
      run_on_every_rank(session, *study, plan, std::max(opt.threads, 1), opt.progress);
  const int rc = summarise(rank, *study, plan);
  print_closing(session, given, opt.progress && rc != 2);
  if (rank == 0 && rc != 2)
    std::fprintf(stderr, "rodend: results in %s\n", plan.dir.string().c_str());
  return rc;
}

}  // namespace rodend::mpi

#else  // a build without MPI: no launcher is ever recognised, so nothing below is reached

#include <stdexcept>

namespace rodend::mpi {

bool built_in() {
  return false;
}
bool launched() {
  return false;
}
Session::Session(bool) {}
Session::~Session() = default;
int run_study_mpi(const Session&, const std::filesystem::path&, const std::filesystem::path&,
                  RunOptions) {
  throw std::logic_error("rodend was built without MPI");
}

}  // namespace rodend::mpi

#endif
