// Distributed runs over MPI; see mpi_runner.hpp. This is the only file that calls MPI.
//
// Protocol (MPI_COMM_WORLD, ints only):
//   worker thread -> rank 0, tag kTagRequest: the status of the case it just finished
//                     (kNone on its first request, kOk, kFailed), i.e. "give me a case";
//   rank 0 -> that rank, tag kTagWork: a case index into Study::cases, or -1: no more work.
// A worker thread holds g_mpi for its whole request/reply round trip, so the reply it receives
// is the one to its own request (MPI_THREAD_SERIALIZED is enough). A rank enters the final
// barrier after each of its threads got -1; rank 0's manager serves requests until that
// barrier completes, so when it does every case handed out has its file under its final name.
//
// Waiting: Open MPI's blocking calls spin a core at 100%. Everything that may wait long (the
// manager's idle time, the end barrier, the broadcasts while rank 0 scans or summarises) polls
// with MPI_Test/MPI_Iprobe and short sleeps instead, so idle ranks and the manager leave the
// cores to the computing threads, also on an oversubscribed node.
#include "sweep/mpi_runner.hpp"

#include <cstdlib>

#ifdef RODEND_HAVE_MPI

#include <mpi.h>
#include <omp.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <cstring>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "sweep/results_dir.hpp"

namespace rodend::mpi {
namespace fs = std::filesystem;

namespace {

constexpr int kTagRequest = 1;
constexpr int kTagWork = 2;
constexpr int kNone = -1, kOk = 0, kFailed = 1;  // request payload
constexpr int kNoMoreWork = -1;                  // reply payload

/// Serialises every MPI call made while threads run (MPI_THREAD_SERIALIZED).
std::mutex g_mpi;
/// The library gave MPI_THREAD_SERIALIZED or better; without it, one thread per rank.
bool g_threads_ok = false;

void sleep_us(int us) {
  std::this_thread::sleep_for(std::chrono::microseconds(us));
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
  int take(int rank) {
    std::lock_guard lock(mutex_);
    if (next_ >= todo_.size()) return kNoMoreWork;
    ++given_[static_cast<std::size_t>(rank)];
    return static_cast<int>(todo_[next_++]);
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

/// Rank 0's manager: answers requests until every other rank has entered the end barrier.
void manage(WorkQueue& queue, Progress& progress) {
  constexpr int kIdlePollUs = 500;
  MPI_Request barrier;
  {
    std::lock_guard lock(g_mpi);
    MPI_Ibarrier(MPI_COMM_WORLD, &barrier);
  }
  for (;;) {
    int pending = 0;
    MPI_Status st;
    {
      std::lock_guard lock(g_mpi);
      MPI_Iprobe(MPI_ANY_SOURCE, kTagRequest, MPI_COMM_WORLD, &pending, &st);
    }
    if (pending) {
      int last = kNone;
      {
        std::lock_guard lock(g_mpi);
        MPI_Recv(&last, 1, MPI_INT, st.MPI_SOURCE, kTagRequest, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
      }
      if (last != kNone) progress.case_done(last != kOk);
      int next = queue.take(st.MPI_SOURCE);
      {
        std::lock_guard lock(g_mpi);
        MPI_Send(&next, 1, MPI_INT, st.MPI_SOURCE, kTagWork, MPI_COMM_WORLD);
      }
      continue;  // drain bursts (every thread asks at the start) without sleeping
    }
    int done = 0;
    {
      std::lock_guard lock(g_mpi);
      MPI_Test(&barrier, &done, MPI_STATUS_IGNORE);
    }
    if (done) return;
    sleep_us(kIdlePollUs);
  }
}

/// A worker thread: asks rank 0 for a case, runs it, writes its file, asks again.
void work_remote(int rank, const Study& study, const RunPlan& plan) {
  try {
    prepare_results_io();  // while memory is free (sweep/results.hpp)
  } catch (const std::bad_alloc&) {
    fatal_out_of_memory(rank);
  }
  int last = kNone;
  for (;;) {
    int i = kNoMoreWork;
    {
      std::lock_guard lock(g_mpi);  // the whole round trip: the reply is to this thread
      MPI_Send(&last, 1, MPI_INT, 0, kTagRequest, MPI_COMM_WORLD);
      MPI_Recv(&i, 1, MPI_INT, 0, kTagWork, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    }
    if (i < 0) return;
    try {
      const CaseRecord rec = run_and_write_case(study, plan, static_cast<std::size_t>(i));
      last = rec.status == "ok" ? kOk : kFailed;
    } catch (const std::bad_alloc&) {
      fatal_out_of_memory(rank);
    } catch (const std::exception& e) {
      fatal(rank, "case " + study.cases[static_cast<std::size_t>(i)].id + ": " + e.what());
    }
  }
}

/// One of rank 0's computing threads: takes cases from the queue directly.
void work_local(const Study& study, const RunPlan& plan, WorkQueue& queue, Progress& progress) {
  try {
    prepare_results_io();  // while memory is free (sweep/results.hpp)
  } catch (const std::bad_alloc&) {
    fatal_out_of_memory(0);
  }
  for (int i = queue.take(0); i >= 0; i = queue.take(0)) {
    try {
      const CaseRecord rec = run_and_write_case(study, plan, static_cast<std::size_t>(i));
      progress.case_done(rec.status != "ok");
    } catch (const std::bad_alloc&) {
      fatal_out_of_memory(0);
    } catch (const std::exception& e) {
      fatal(0, "case " + study.cases[static_cast<std::size_t>(i)].id + ": " + e.what());
    }
  }
}

/// Reads the record of a case another rank wrote. On a network file system a file renamed on
/// one node may take a few seconds to show on another (cached directory entries): retries for
/// up to 60 s, listing the directory to revalidate it, before giving up.
CaseRecord read_back(const fs::path& cases_dir, const CaseSpec& c) {
  const fs::path path = cases_dir / (c.id + ".h5");
  const auto t0 = std::chrono::steady_clock::now();
  for (;;) {
    if (auto rec = read_case_record(path)) return *rec;
    if (std::chrono::steady_clock::now() - t0 > std::chrono::seconds(60))
      throw std::runtime_error("case " + c.id + " was run but " + path.string() +
                               " cannot be read on rank 0");
    std::error_code ec;
    for (fs::directory_iterator it(cases_dir, ec), end; !ec && it != end; it.increment(ec)) {
    }
    sleep_us(500000);
  }
}

/// Ends this rank when its launcher dies. A SIGKILL to mpirun (or to the orted of a node) does
/// not reach the ranks, each in a process group of its own, and Open MPI does not stop them
/// either: rank 0's computing threads never talk to anyone, and the others talk only to rank 0.
/// Left alone they would run on as orphans. The rank's parent is the launcher (mpirun, orted or
/// slurmstepd); when it changes, the launcher is gone and the rank exits at once (files being
/// written stay under their hidden temporary names: resume reruns those cases).
class LauncherWatch {
 public:
  LauncherWatch() : parent_(::getppid()), thread_([this] { watch(); }) {}
  ~LauncherWatch() {
    {
      std::lock_guard lock(mutex_);
      stop_ = true;
    }
    wake_.notify_all();
    thread_.join();
  }
  LauncherWatch(const LauncherWatch&) = delete;
  LauncherWatch& operator=(const LauncherWatch&) = delete;

 private:
  void watch() {
    std::unique_lock lock(mutex_);
    while (!wake_.wait_for(lock, std::chrono::milliseconds(200), [this] { return stop_; })) {
      if (::getppid() != parent_) {
        std::fprintf(stderr, "rodend: the MPI launcher is gone; this rank stops\n");
        std::fflush(stderr);
        std::_Exit(3);
      }
    }
  }
  const pid_t parent_;
  std::mutex mutex_;
  std::condition_variable wake_;
  bool stop_ = false;
  std::thread thread_;  // last: started once the members above exist
};

/// A fingerprint of a loaded study: every rank must run the same cases into the same place.
std::string fingerprint(const Study& s) {
  std::string text = fs::absolute(s.output_dir).lexically_normal().string();
  for (const CaseSpec& c : s.cases) {
    text += '\n';
    text += c.id;
  }
  return fnv1a64_hex(text);
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
  const LauncherWatch watch;

  // 1. every rank loads the study; all must agree on it (the same file on every node)
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
  if (!all_ok) return 2;

  if (!g_threads_ok && opt.threads > 1) {
    if (rank == 0)
      std::fprintf(stderr,
                   "rodend: warning: the MPI library does not allow calls from several "
                   "threads; running one case at a time per rank\n");
    opt.threads = 1;
  }
  const int threads = std::max(opt.threads, 1);

  // 2. rank 0 decides what to run from the case files present, exactly as run_study does
  RunPlan plan;
  int status = 0;
  if (rank == 0) {
    try {
      plan = plan_run(*study, opt);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "rodend: error: %s\n", e.what());
      status = 2;
    }
  }
  bcast_int_polled(status);
  if (status != 0) return status;
  if (rank != 0) {  // what a worker needs of the plan
    plan.dir = study->output_dir;
    plan.cases_dir = plan.dir / "cases";
    plan.provenance = provenance(*study);  // this rank's host goes into the files it writes
  }

  // 3. run: rank 0 manages (thread 0) and computes (threads 1..T); the others compute
  std::vector<long> given;  // rank 0: cases run by each rank
  if (rank == 0) {
    Progress progress(opt.progress, plan.in_scope,
                      plan.in_scope - static_cast<long>(plan.todo.size()));
    WorkQueue queue(plan.todo, session.size());
#pragma omp parallel num_threads(threads + 1)
    {
      if (omp_get_thread_num() == 0)
        manage(queue, progress);
      else
        work_local(*study, plan, queue, progress);
    }
    given = queue.given();
  } else {
#pragma omp parallel num_threads(threads)
    work_remote(rank, *study, plan);
    MPI_Request barrier;
    {
      std::lock_guard lock(g_mpi);
      MPI_Ibarrier(MPI_COMM_WORLD, &barrier);
    }
    wait_polled(barrier);
  }

  // 4. rank 0 assembles the summary from the case files; everyone returns its exit code
  int rc = 0;
  if (rank == 0) {
    try {
      for (const std::size_t i : plan.todo)
        plan.spool->put(i, read_back(plan.cases_dir, study->cases[i]));
      rc = write_run_summary(*study, plan);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "rodend: error: %s\n", e.what());
      rc = 2;
    }
  }
  bcast_int_polled(rc);
  if (rank == 0 && rc != 2 && opt.progress) {
    std::string per_rank;
    for (const long n : given) per_rank += " " + std::to_string(n);
    std::fprintf(stderr, "rodend: %d MPI ranks, cases run by rank 0..%d:%s\n", session.size(),
                 session.size() - 1, per_rank.c_str());
  }
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
