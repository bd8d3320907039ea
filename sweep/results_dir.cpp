#include "sweep/results_dir.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <csignal>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "core/errors.hpp"

namespace rodend {
namespace fs = std::filesystem;

namespace {

bool all_digits(const std::string& s) {
  return !s.empty() && s.find_first_not_of("0123456789") == std::string::npos;
}

/// Names a results directory of rodend holds (any version): what may be in a directory that is
/// adopted without a marker.
bool rodend_name(const std::string& name) {
  static const std::array<const char*, 9> kNames{"study.json", "summary.h5",  "summary.csv",
                                                 "cases",      "plots",       "design.json",
                                                 "analysis",   "report.html", "profiles.json"};
  for (const char* n : kNames)
    if (name == n) return true;
  if (name.rfind("shard-", 0) == 0) return true;                       // shard summaries
  if (name.front() == '.' && name.find(".tmp.") != std::string::npos)  // temporaries
    return true;
  return false;
}

/// Who holds the lock, as written into the lock file by the holder.
std::string read_holder(const fs::path& lock_path) {
  std::ifstream in(lock_path);
  std::string line;
  std::getline(in, line);
  return line.empty() ? "another process" : line;
}

int remove_stale_temporaries(const fs::path& dir) {
  int removed = 0;
  std::error_code ec;
  for (auto it = fs::recursive_directory_iterator(dir, ec); !ec && it != fs::end(it);
       it.increment(ec)) {
    if (it.depth() > 1) {  // dir, dir/cases, dir/shard-*: nothing deeper is rodend's
      it.disable_recursion_pending();
      continue;
    }
    std::error_code ignored;
    if (!it->is_regular_file(ignored)) continue;
    if (!is_stale_temporary(it->path().filename().string())) continue;
    if (fs::remove(it->path(), ignored)) ++removed;
  }
  return removed;
}

/// Creates the marker file of a results directory rodend created (never through a link: a
/// planted one is refused).
void write_marker(const fs::path& marker, const std::string& study_file) {
  static const char text[] =
      "This directory holds rodend results; rodend created it and may write here.\n";
  std::error_code ignored;
  if (fs::is_regular_file(fs::symlink_status(marker, ignored))) return;  // there already
  const int fd = ::open(marker.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0644);
  if (fd < 0) {
    const int err = errno;
    std::error_code ec;
    if (err == EEXIST && fs::is_regular_file(fs::symlink_status(marker, ec))) return;
    throw InputError("output",
                     err == EEXIST ? marker.string() +
                                         " exists and is not a regular file (a link?); "
                                         "rodend writes its marker there: remove it"
                                   : "the results directory " + marker.parent_path().string() +
                                         " is not writable (cannot create " + marker.string() +
                                         ": " + std::strerror(err) + ")",
                     study_file);
  }
  const bool ok = ::write(fd, text, sizeof text - 1) == static_cast<ssize_t>(sizeof text - 1);
  if (::close(fd) != 0 || !ok)
    throw InputError("output",
                     "the results directory " + marker.parent_path().string() + " is not writable",
                     study_file);
}

/// Opens (creating it if needed) the lock file `lock_path`: never through a symbolic link, and
/// only a regular file with no other name (a hard link planted there would have its other
/// name's content replaced by the holder's name). Refused otherwise (InputError, exit 2).
int open_lock_file(const fs::path& lock_path, const std::string& study_file) {
  const int fd =
      ::open(lock_path.c_str(), O_RDWR | O_CREAT | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC, 0644);
  if (fd < 0) {
    const int err = errno;
    throw InputError("output",
                     err == ELOOP ? "the lock file " + lock_path.string() +
                                        " is a symbolic link; rodend never writes through a "
                                        "link: remove it (rodend creates the lock file itself)"
                                  : "the results directory " + lock_path.parent_path().string() +
                                        " is not writable (cannot create its lock file " +
                                        lock_path.string() + ": " + std::strerror(err) + ")",
                     study_file);
  }
  struct stat st {};
  if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode) || st.st_nlink != 1) {
    ::close(fd);
    throw InputError("output",
                     "the lock file " + lock_path.string() +
                         " is not a regular file of its own (a device, or a hard link to another "
                         "file); rodend never writes into it: remove it (rodend creates the "
                         "lock file itself)",
                     study_file);
  }
  return fd;
}

}  // namespace

std::string host_name() {
  char host[256] = {};
  if (::gethostname(host, sizeof host - 1) != 0 || host[0] == '\0') return "unknown-host";
  return host;
}

bool is_stale_temporary(const std::string& name) {
  const auto tmp = name.find(".tmp.");
  if (name.empty() || name.front() != '.' || tmp == std::string::npos) return false;
  // .<name>.tmp.<host>.<pid>.<n>, older .<name>.tmp.<pid>.<n> and .<name>.tmp.<host>.<pid>
  std::vector<std::string> parts;
  std::stringstream rest(name.substr(tmp + 5));
  for (std::string p; std::getline(rest, p, '.');) parts.push_back(p);
  if (parts.empty()) return false;
  std::string pid, host;
  const std::size_t n = parts.size();
  if (n >= 2 && all_digits(parts[n - 1]) && all_digits(parts[n - 2])) {
    pid = parts[n - 2];
    for (std::size_t i = 0; i + 2 < n; ++i) host += (i ? "." : "") + parts[i];
  } else if (all_digits(parts[n - 1])) {
    pid = parts[n - 1];
    for (std::size_t i = 0; i + 1 < n; ++i) host += (i ? "." : "") + parts[i];
  } else {
    return false;
  }
  if (!host.empty() && host != host_name()) return false;  // another node's writer: unknown
  if (pid.size() > 9) return false;
  const pid_t p = static_cast<pid_t>(std::stol(pid));
  if (p <= 0) return false;
  return ::kill(p, 0) != 0 && errno == ESRCH;
}

namespace {

/// Creates `dir` (with its marker) or checks that rodend may write there: a directory it
/// created (the marker), an empty one, or one of an earlier rodend version (cases/ and rodend's
/// own names only), which is adopted and marked. Throws InputError (key "output") otherwise.
void claim_directory(const fs::path& dir, const std::string& study_file) {
  std::error_code ec;
  const fs::path marker = dir / kResultsMarker;
  const bool existed = fs::exists(dir, ec);
  if (existed && !fs::is_directory(dir, ec))
    throw InputError("output",
                     "the results path " + dir.string() + " exists and is not a directory",
                     study_file);
  if (existed && !fs::exists(marker, ec)) {
    bool has_cases = false, foreign = false;
    std::string foreign_name;
    for (const auto& e : fs::directory_iterator(dir, ec)) {
      const std::string name = e.path().filename().string();
      if (name == "cases") has_cases = true;
      if (!rodend_name(name) && !foreign) {
        foreign = true;
        foreign_name = name;
      }
    }
    const bool empty = fs::is_empty(dir, ec);
    if (!empty && (foreign || !has_cases))
      throw InputError(
          "output",
          "the results directory " + dir.string() +
              " is not empty and was not created by rodend (no " + kResultsMarker + " marker" +
              (foreign ? "; it holds '" + foreign_name + "'" : "") +
              "); rodend never overwrites files it did not create: expected a new or empty "
              "directory, or one of rodend's results directories",
          study_file);
  }
  fs::create_directories(dir, ec);
  if (ec)
    throw InputError("output",
                     "cannot create the results directory " + dir.string() + ": " + ec.message(),
                     study_file);
  write_marker(marker, study_file);
}

/// Takes flock `mode` (LOCK_SH, LOCK_EX) on `fd`, the lock file `lock_path`: at once, or, when
/// another run holds it, waiting (`wait`) or throwing a message naming the holder. Closes `fd`
/// when it throws.
void take_lock(int fd, const fs::path& lock_path, int mode, bool wait) {
  if (::flock(fd, mode | LOCK_NB) == 0) return;
  const int err = errno;
  if (err != EWOULDBLOCK) {
    ::close(fd);
    throw std::runtime_error("cannot lock " + lock_path.string() + ": " + std::strerror(err));
  }
  const std::string holder = read_holder(lock_path);
  if (!wait) {
    ::close(fd);
    throw std::runtime_error("another run of this study holds " + lock_path.string() + " (" +
                             holder +
                             "); wait for it to finish, or rerun with --wait to queue "
                             "behind it");
  }
  std::fprintf(stderr, "rodend: waiting for the run that holds %s (%s)\n", lock_path.c_str(),
               holder.c_str());
  while (::flock(fd, mode) != 0) {
    if (errno != EINTR) {
      const int e = errno;
      ::close(fd);
      throw std::runtime_error("cannot lock " + lock_path.string() + ": " + std::strerror(e));
    }
  }
}

}  // namespace

std::unique_ptr<ResultsLock> ResultsLock::claim(const fs::path& dir, const std::string& lock_name,
                                                const std::string& study_file, bool wait,
                                                bool shared) {
  claim_directory(dir, study_file);
  // the lock: flock on a file of its own, held until the run ends (closing the descriptor, or
  // the process's death, releases it)
  const fs::path lock_path = dir / lock_name;
  const int fd = open_lock_file(lock_path, study_file);
  take_lock(fd, lock_path, shared ? LOCK_SH : LOCK_EX, wait);
  // the holder's name, for the message of a second run
  const std::string who = "pid " + std::to_string(::getpid()) + " on " + host_name() + "\n";
  if (::ftruncate(fd, 0) == 0) {
    const ssize_t w = ::pwrite(fd, who.data(), who.size(), 0);
    (void)w;  // informational only
  }
  std::unique_ptr<ResultsLock> lock(new ResultsLock(fd, lock_path));
  lock->stale_removed_ = remove_stale_temporaries(dir);
  return lock;
}

ResultsLock::~ResultsLock() {
  if (fd_ >= 0) ::close(fd_);
}

}  // namespace rodend
