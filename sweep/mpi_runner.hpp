// Distributed runs: one study over the ranks of an MPI job (`mpirun -np N rodend run S.json`).
//
// Scheduling: dynamic manager/worker. Rank 0 decides what to run exactly as run_study does
// (the case files present, --rerun-failed, --shard) and hands out case indices to whichever
// thread of whichever rank asks; rank 0 also computes: its manager is one extra thread that
// polls for requests, so `-np 2` has two computing ranks. Each rank runs --threads OpenMP
// threads, each asking for its own next case (one request ahead while many are left). Each case
// file is written by the rank that ran it (write_case_file: temporary name, rename); its record
// travels to rank 0 with the worker's next request and goes into the summary's spool, so rank 0
// writes the summary without reading case files back. Without MPI in the build, or outside an
// MPI launcher, none of this is used.
//
// Errors: bad input or an unusable results directory: every rank returns 2 (message on rank
// 0's stderr). A case that fails numerically is a failed case record, and its rank goes on. A
// case file that cannot be written ends the job: message on stderr, then MPI_Abort(..., 2).
// SIGINT or SIGTERM: each rank abandons its cases in flight and exits 128 + N at once, rank 0
// after printing the count of complete cases and the resume command.
#pragma once

#include <filesystem>

#include "sweep/runner.hpp"

namespace rodend::mpi {

/// True in a build with MPI support (CMake option RODEND_MPI and MPI found).
bool built_in();

/// True when this process was started by an MPI launcher: Open MPI's mpirun
/// (OMPI_COMM_WORLD_SIZE), a PMIx launcher such as `srun --mpi=pmix` (PMIX_RANK) or a PMI one
/// (PMI_RANK, PMI_SIZE). Looks at the environment only. Always false without MPI in the build.
bool launched();

/// MPI for the lifetime of the object (MPI_Init_thread ... MPI_Finalize), initialised only when
/// `wanted` and built with MPI; otherwise this is rank 0 of 1 and nothing is called.
class Session {
 public:
  explicit Session(bool wanted);
  ~Session();
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;
  bool active() const { return active_; }
  int rank() const { return rank_; }
  int size() const { return size_; }

 private:
  bool active_ = false;
  int rank_ = 0, size_ = 1;
};

/// `rodend run` over all ranks of an active session with size() > 1. Every rank loads the study
/// (they must agree on it: same case ids, same results directory). Returns the exit code, the
/// same on every rank: 0 every case ok, 1 a case failed, 2 bad input or results directory (the
/// message on stderr). Never throws; ends the job with MPI_Abort when a case file cannot be
/// written, and the rank with _Exit(128 + N) on SIGINT or SIGTERM.
int run_study_mpi(const Session& session, const std::filesystem::path& study_file,
                  const std::filesystem::path& results_root, RunOptions options);

}  // namespace rodend::mpi
