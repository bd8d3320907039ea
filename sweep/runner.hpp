// Running a study: every case not yet complete, in parallel over cases (OpenMP, dynamic
// scheduling), each case written to its own file as it finishes, then the summary.
//
// Thread-safety rule: a Scene is immutable and built per case; the driver, its scratch, the
// recorder and the metrics belong to one case on one thread; nothing in the physics is shared
// mutably between threads. All HDF5 I/O goes through sweep/results.hpp, which serialises it.
#pragma once

#include <iosfwd>

#include "sweep/results.hpp"
#include "sweep/study.hpp"

namespace rodend {

struct RunOptions {
  int threads = 1;            ///< OpenMP threads over cases
  bool rerun_failed = false;  ///< rerun cases whose stored status is a failure
  bool progress = true;       ///< progress on stderr
  int shard_index = 1;        ///< run only the shard_index-th of shard_count slices (1-based)
  int shard_count = 1;
};

/// Runs one case in memory: builds the scene, integrates, records histories and metrics.
/// Never throws for numerical trouble (the record's status says it); throws InputError only
/// for a case that does not build.
CaseRecord run_case(const CaseSpec& spec, History& history);

/// Runs a study and writes its results. Returns the process exit code: 0 when every case is ok,
/// 1 when at least one failed. Throws InputError / std::runtime_error for problems with the
/// output directory.
int run_study(const Study& study, const RunOptions& options);

/// The cases of one shard: case index i belongs to shard (i mod N) + 1.
bool in_shard(const CaseSpec& c, const RunOptions& o);

}  // namespace rodend
