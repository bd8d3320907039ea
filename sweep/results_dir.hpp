// The results directory of a study, owned by rodend.
//
// - Ownership: rodend writes a marker file (`.rodend`) into a results directory when it creates
//   it. A non-empty directory without the marker is refused (rodend never overwrites or deletes
//   a file it did not create), except a results directory of an earlier rodend version (it has
//   `cases/` and only the names rodend writes), which is adopted and marked.
// - One run at a time: the run holds an advisory lock (`flock`) on `.rodend.lock` for its whole
//   life: exclusive for a full run and a merge; a shard holds it shared and
//   `.rodend.lock.shard-K-of-N` exclusive, so that the shards of one study run side by side
//   while a full run of the same folder waits for them (and they for it). A second run of the same
//   study refuses with a message naming the holder, or waits for it (`rodend run --wait`).
// - Stale temporary files: under the lock, the temporary files of writers that are no longer
//   running on this host (`.<name>.tmp.<host>.<pid>.<n>`, and the older `.<name>.tmp.<pid>.<n>`)
//   are removed.
#pragma once

#include <filesystem>
#include <memory>
#include <string>

namespace rodend {

/// Name of the ownership marker in a results directory.
inline constexpr const char* kResultsMarker = ".rodend";

/// The held lock of a results directory; released (and its file descriptor closed) on
/// destruction.
class ResultsLock {
 public:
  ResultsLock(const ResultsLock&) = delete;
  ResultsLock& operator=(const ResultsLock&) = delete;
  ~ResultsLock();

  /// Claims `dir` for a run: creates it (with the marker) or checks that rodend owns it, takes
  /// the lock named `lock_name` (waiting when `wait`, else throwing a std::runtime_error naming
  /// the holder), then removes stale temporary files in `dir` and its subdirectories.
  /// `shared`: a shared hold (flock LOCK_SH), which excludes only the exclusive ones.
  /// Throws InputError (key "output", in `study_file`) for a directory rodend does not own.
  static std::unique_ptr<ResultsLock> claim(const std::filesystem::path& dir,
                                            const std::string& lock_name,
                                            const std::string& study_file, bool wait,
                                            bool shared = false);

  /// Number of stale temporary files removed by claim().
  int stale_removed() const { return stale_removed_; }

 private:
  ResultsLock(int fd, std::filesystem::path path) : fd_(fd), path_(std::move(path)) {}
  int fd_ = -1;
  std::filesystem::path path_;
  int stale_removed_ = 0;
};

/// This host's name, as used in temporary file names ("unknown-host" when it cannot be read).
std::string host_name();

/// True when `name` is a rodend temporary file (`.<name>.tmp.<...>`) whose writer is known to
/// be gone: written on this host (or before host names were recorded) by a process that is not
/// running.
bool is_stale_temporary(const std::string& name);

}  // namespace rodend
