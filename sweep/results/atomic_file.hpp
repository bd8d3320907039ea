// The one atomic file writer of rodend: every file the results code writes (case files, the
// summary, study.json, design.json, the report) goes through AtomicFile.
//
// A file is written under a hidden temporary name in its final directory
// (.<name>.tmp.<host>.<pid>.<random>, created with O_EXCL|O_NOFOLLOW: never an existing file,
// never through a link, a name nobody can plant beforehand), closed, then renamed to its final
// name (renameat, atomic on POSIX; a link under the final name is replaced, not followed). A
// failed write removes the temporary file and throws; a partially written file never appears
// under the final name. Case files are not fsync'd: one torn by an OS crash fails its checksum
// (checksum.hpp) and resume reruns it; summary.h5, summary.csv and their directory are.
#pragma once

#include <sys/types.h>

#include <filesystem>
#include <initializer_list>
#include <span>
#include <string>

namespace rodend::results_detail {

namespace fs = std::filesystem;

using ByteSpan = std::span<const unsigned char>;

/// The bytes of `text` (a view: `text` must outlive it).
ByteSpan bytes_of(const std::string& text);

/// `.<name>.tmp.<host>.<pid>.<random>` beside `path`: the host and pid tell a later run whether
/// its writer is gone (sweep/results_dir.hpp); the random part (64 bits from getrandom(2), in
/// decimal) makes the name unpredictable, so that nobody can plant a link under it beforehand.
fs::path temp_path_for(const fs::path& path);

/// write(2) of all of `bytes` to `fd` (pwrite(2) at `offset` when it is not negative), with the
/// injected failure of WriteFailureInjection. Returns 0 or the errno of the failure.
int write_all(int fd, const unsigned char* bytes, std::size_t size, off_t offset = -1);

/// A file replaced atomically: written under a hidden temporary name in the same directory with
/// write(2) (every failure, a full disk included, is this class's error message naming the
/// final path, never HDF5's), optionally flushed to the disk, then renamed over the final path.
/// On any failure, and when destroyed before commit(), the temporary file is removed and the
/// final path is left as it was. Writing in pieces keeps a large file (summary.csv) from being
/// held whole in memory.
class AtomicFile {
 public:
  /// Creates the temporary file beside `path` (and `path`'s directory if needed); `what` names
  /// the file in messages ("results file", "summary file").
  AtomicFile(fs::path path, std::string what);
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;
  ~AtomicFile();

  /// Appends `bytes` to the temporary file; throws (the temporary file removed) on failure.
  void write(ByteSpan bytes);
  /// The temporary file, for a writer of its own (the summary's HDF5 driver, the sink driver).
  int fd() const { return fd_; }
  /// That writer's failure (`err`: its errno): throws this class's message, as write() does.
  [[noreturn]] void fail_write(int err);
  /// Everything is written: flushes it to the disk (durable) and closes the temporary file.
  void finish(bool durable);
  /// Renames the finished file over the final path, in the same directory (a link under the
  /// final name is replaced, not followed), and, durable, flushes the directory, so that the
  /// rename is there after an OS crash.
  void commit(bool durable);

 private:
  [[noreturn]] void fail(const std::string& step, int err);

  fs::path path_, temp_;
  std::string what_;
  int dir_fd_ = -1;
  int fd_ = -1;
  bool committed_ = false;
};

/// Writes `parts` (in order) to `path` atomically (AtomicFile), optionally flushed to the disk
/// (`durable`). Throws std::runtime_error naming `path`; `path` is then left as it was.
void write_file_atomically(const fs::path& path, const std::string& what,
                           std::initializer_list<ByteSpan> parts, bool durable);

}  // namespace rodend::results_detail
