// Running a study: every case not yet complete, in parallel over cases (OpenMP, dynamic
// scheduling), each case written to its own file as it finishes, then the summary.
//
// Thread-safety rule: a Scene is immutable and built per case; the driver, its scratch, the
// recorder and the metrics belong to one case on one thread; nothing in the physics is shared
// mutably between threads. All HDF5 I/O goes through sweep/results.hpp, which serialises it.
//
// The building blocks below (plan_run, run_and_write_case, Progress, read_records) are shared
// by run_study (one process), the MPI runner (sweep/mpi_runner.hpp: one study over the ranks of
// an mpirun job) and merge_study (the summary of a study run in shards).
#pragma once

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <iosfwd>
#include <memory>
#include <mutex>
#include <new>
#include <string>

#include "sweep/results.hpp"
#include "sweep/results_dir.hpp"
#include "sweep/study.hpp"

namespace rodend {

/// Where a run's messages and progress go: empty, on stderr (the command line); the Python
/// module sets both (Python's logging, a progress bar or the caller's callback). Called from the
/// worker threads too (one call at a time).
struct RunEvents {
  /// one message, as the command line prints it after "rodend: " (no newline)
  std::function<void(const std::string& text)> message;
  /// after each case: cases complete (those of earlier runs included), of total, failed, the
  /// seconds since the start and the estimated seconds left
  std::function<void(long done, long total, long failed, double elapsed_s, double eta_s)> progress;
};

/// A run's message: to events.message when set, else "rodend: TEXT" on stderr.
void run_message(const RunEvents& events, const std::string& text);

struct RunOptions {
  int threads = 1;            ///< OpenMP threads over cases (per rank under MPI)
  bool rerun_failed = false;  ///< rerun cases whose stored status is a failure
  bool progress = true;       ///< progress on stderr
  int shard_index = 1;        ///< run only the shard_index-th of shard_count slices (1-based)
  int shard_count = 1;
  bool wait = false;  ///< wait for another run of the same study instead of refusing
  std::vector<std::string> overrides;  ///< --set key=value, applied to the study (MPI ranks)
  RunEvents events;                    ///< messages and progress (default: stderr)
};

/// Runs one case in memory: builds the scene, integrates, records histories and metrics.
/// Numerical trouble is the record's status, and any exception (a scene that fails to build or
/// throws while it runs, an internal bug) is stored as internal_error with its message, so the
/// other cases of a study go on; but running out of memory is the environment's failure, not
/// the case's: std::bad_alloc propagates (and nothing is recorded).
CaseRecord run_case(const CaseSpec& spec, History& history);

/// Runs a study and writes its results. Returns the process exit code: 0 when every case is ok,
/// 1 when at least one failed. Throws InputError / std::runtime_error for problems with the
/// output directory, OutOfMemory when memory runs out in any thread (no case is recorded as
/// failed for it), std::runtime_error when the threads cannot be started; each message gives
/// the count of complete cases and the resume command.
int run_study(const Study& study, const RunOptions& options);

/// Memory ran out during a run (in any thread): an environment failure, not a case result.
/// what(): the count of complete cases and the command to resume, composed into a buffer of
/// the object itself (nothing allocated on the way to the message).
class OutOfMemory : public std::bad_alloc {
 public:
  OutOfMemory(long complete, long in_scope, const char* cases_dir, const char* resume) noexcept;
  const char* what() const noexcept override { return text_; }

 private:
  char text_[4096];
};

/// The command that resumes the run of `study` with `options`: `rodend run STUDY` with every
/// option that changes what it runs or where (--results-root, --set, --shard, --rerun-failed),
/// quoted for a POSIX shell.
std::string resume_command(const Study& study, const RunOptions& options);

/// The cases of one shard: case index i belongs to shard (i mod N) + 1.
bool in_shard(const CaseSpec& c, const RunOptions& o);

/// Assembles `study.output_dir`/summary.{h5,csv} from the case files in
/// `study.output_dir`/cases (every case of the study, whichever shard or rank wrote it).
/// Returns 0 when every case has a complete file (failed cases included: their status is in the
/// summary), 1 when some are missing: they are listed on `report` and no summary is written.
int merge_study(const Study& study, std::ostream& report);

// ---------------------------------------------------------------------------------------------
// Building blocks

/// What a run has to do, decided from the case files present (resume).
struct RunPlan {
  std::filesystem::path dir;          ///< the study's results directory
  std::filesystem::path cases_dir;    ///< dir/cases
  std::filesystem::path summary_dir;  ///< dir, or dir/shard-K-of-N for a shard
  Json provenance;
  /// the records of the complete cases, on the disk (memory flat in the number of cases): the
  /// summary's rows
  std::unique_ptr<RecordSpool> spool;
  std::vector<std::size_t> todo;      ///< case indices to run, largest first (case_order.hpp)
  long in_scope = 0;                  ///< cases of this shard (all cases without shards)
  std::shared_ptr<ResultsLock> lock;  ///< held for the run (sweep/results_dir.hpp)
  /// a shard's shared hold on the study's lock: full runs and merges wait for the shards
  std::shared_ptr<ResultsLock> study_lock;
  std::string resume;  ///< resume_command(study, options), for the messages that stop a run
  /// per case of the study (slot): 0 when it has no row in the spool, else the identity of its
  /// file when its case id was known to hold (read at resume, or written by this run:
  /// case_file_stamp; 2 when there was none to take). The check before the summary reads again
  /// only the files whose identity changed (write_run_summary).
  mutable std::vector<std::uint64_t> stamps;
};

/// The identity of the regular file at `path` (device, inode, size, modification and change
/// times: a file replaced, renamed over or rewritten gets another), 0 when there is none.
std::uint64_t case_file_stamp(const std::filesystem::path& path);

/// The files of the rows of plan.spool: each is there and holds its case (a file whose
/// identity changed since it was noted is read again: checksum and case id). Throws
/// std::runtime_error naming those that are gone or hold another case, with the count of
/// complete cases and the resume command (sweep/case_file_check.cpp).
void check_case_files(const RunPlan& plan);

/// Records the identity of the file of case `i` (id `id`), just written (thread-safe for
/// distinct cases; nothing when the plan does not track case `i`: an MPI rank's own plan).
void note_case_file(const RunPlan& plan, std::size_t i, const std::string& id);

/// Claims the results directory (ownership marker, lock, stale temporaries removed:
/// sweep/results_dir.hpp), creates its subdirectories, writes study.json, and reads the case
/// files present: a complete case is kept (unless failed and options.rerun_failed), the others
/// are to run. Throws InputError when the results directory cannot be created or written or is
/// not rodend's, std::runtime_error when another run holds it.
RunPlan plan_run(const Study& study, const RunOptions& options);

/// Runs case `i` of the study and writes its file into plan.cases_dir. Returns its record;
/// throws std::runtime_error when the file cannot be written (or InputError when the case
/// does not build).
CaseRecord run_and_write_case(const Study& study, const RunPlan& plan, std::size_t i);

/// Writes the summary of the records in plan.spool (grid order) into plan.summary_dir, after
/// checking that every row's case file is there and holds its case (a file whose identity
/// changed since it was verified is read again): throws std::runtime_error naming those that
/// are gone or hold another case, with the count and the resume command, and writes nothing.
/// Returns 0 when every row is ok, 1 otherwise.
int write_run_summary(const Study& study, const RunPlan& plan);

/// Progress on stderr: one updating line on a terminal, periodic plain lines otherwise; or to
/// `events` when they are set. Thread-safe.
class Progress {
 public:
  Progress(bool enabled, long total, long already, const RunEvents& events = {});
  void case_done(bool failed);
  /// Ends the updating progress line of a terminal, so that a message after it (the stop after
  /// a signal) starts on a line of its own.
  void break_line();

 private:
  RunEvents events_;
  bool enabled_, tty_;
  bool line_open_ = false;  // an updating line without its newline is on the terminal
  long total_, done_, failed_ = 0;
  std::chrono::steady_clock::time_point start_;
  long already_;
  double last_print_ = 0.0;
  std::mutex mutex_;
};

}  // namespace rodend
