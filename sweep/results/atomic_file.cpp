// The atomic file writer (sweep/results/atomic_file.hpp) and the injected write failures of the
// tests (WriteFailureInjection).
#include "sweep/results/atomic_file.hpp"

#include <fcntl.h>
#include <sys/random.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstring>
#include <ctime>
#include <stdexcept>

#include "sweep/results.hpp"
#include "sweep/results/hdf5.hpp"
#include "sweep/results_dir.hpp"

namespace rodend::results_detail {

ByteSpan bytes_of(const std::string& text) {
  return ByteSpan(reinterpret_cast<const unsigned char*>(text.data()), text.size());
}

fs::path temp_path_for(const fs::path& path) {
  static const std::string host = host_name();
  std::uint64_t r = 0;
  if (::getrandom(&r, sizeof r, 0) != static_cast<ssize_t>(sizeof r)) {
    // no entropy source (very old kernels): the clock and a counter (O_EXCL still holds)
    static std::atomic<std::uint64_t> counter{0};
    r = static_cast<std::uint64_t>(clock_ns(CLOCK_REALTIME)) * 1000003u + counter.fetch_add(1);
  }
  const std::string name = "." + path.filename().string() + ".tmp." + host + "." +
                           std::to_string(static_cast<long long>(::getpid())) + "." +
                           std::to_string(r);
  return path.parent_path() / name;
}

namespace {

/// Bytes a WriteFailureInjection still lets through (negative: no injection in place).
std::atomic<long long> g_write_budget{-1};

}  // namespace

int write_all(int fd, const unsigned char* bytes, std::size_t size, off_t offset) {
  while (size > 0) {
    std::size_t n = std::min<std::size_t>(size, std::size_t{1} << 30);
    const long long budget = g_write_budget.load();
    if (budget >= 0) {
      if (budget == 0) return ENOSPC;
      n = std::min<std::size_t>(n, static_cast<std::size_t>(budget));
      g_write_budget.fetch_sub(static_cast<long long>(n));
    }
    const ssize_t w = offset < 0 ? ::write(fd, bytes, n) : ::pwrite(fd, bytes, n, offset);
    if (w < 0) {
      if (errno == EINTR) continue;
      return errno;
    }
    if (offset >= 0) offset += w;
    bytes += w;
    size -= static_cast<std::size_t>(w);
  }
  return 0;
}

AtomicFile::AtomicFile(fs::path path, std::string what)
    : path_(std::move(path)), what_(std::move(what)) {
  if (path_.filename().empty())
    throw std::runtime_error("cannot write " + path_.string() + ": not a file name");
  std::error_code ec;
  const fs::path dir = path_.parent_path();
  if (!dir.empty()) {
    fs::create_directories(dir, ec);
    if (ec)
      throw std::runtime_error("cannot write " + what_ + " " + path_.string() +
                               ": cannot create directory " + dir.string() + ": " + ec.message());
  }
  // the directory, opened once: the temporary file is created, renamed and removed in it
  // (*at calls), whatever happens to the path to it meanwhile
  dir_fd_ = ::open(dir.empty() ? "." : dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dir_fd_ < 0)
    throw std::runtime_error("cannot write " + what_ + " " + path_.string() +
                             ": cannot open directory " + dir.string() + ": " +
                             std::strerror(errno));
  // created fresh (O_EXCL: never an existing file, never through a link) under a name
  // nobody can guess; read-write: the summary's HDF5 driver reads back what it wrote
  for (int attempt = 0; fd_ < 0; ++attempt) {
    temp_ = temp_path_for(path_);
    fd_ = ::openat(dir_fd_, temp_.filename().c_str(),
                   O_RDWR | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0644);
    const int err = errno;
    if (fd_ < 0 && (err != EEXIST || attempt == 16)) {
      ::close(dir_fd_);
      throw std::runtime_error("cannot write " + what_ + " " + path_.string() + ": cannot create " +
                               temp_.string() + ": " + std::strerror(err));
    }
  }
}

AtomicFile::~AtomicFile() {
  if (fd_ >= 0) ::close(fd_);
  if (!committed_) ::unlinkat(dir_fd_, temp_.filename().c_str(), 0);
  ::close(dir_fd_);
}

void AtomicFile::write(ByteSpan bytes) {
  if (const int err = write_all(fd_, bytes.data(), bytes.size()); err != 0) fail_write(err);
}

void AtomicFile::fail_write(int err) {
  fail("write error on " + temp_.string(), err);
}

void AtomicFile::finish(bool durable) {
  int err = 0;
  if (durable && ::fsync(fd_) != 0) err = errno;
  if (::close(fd_) != 0 && err == 0) err = errno;
  fd_ = -1;
  if (err != 0) fail("write error on " + temp_.string(), err);
}

void AtomicFile::commit(bool durable) {
  if (::renameat(dir_fd_, temp_.filename().c_str(), dir_fd_, path_.filename().c_str()) != 0)
    fail("cannot rename " + temp_.string(), errno);
  committed_ = true;
  if (durable) (void)::fsync(dir_fd_);  // best effort: not every file system syncs a directory
}

void AtomicFile::fail(const std::string& step, int err) {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
  if (!committed_) ::unlinkat(dir_fd_, temp_.filename().c_str(), 0);
  committed_ = true;  // nothing left to remove
  throw std::runtime_error("cannot write " + what_ + " " + path_.string() + ": " + step + ": " +
                           std::strerror(err));
}

void write_file_atomically(const fs::path& path, const std::string& what,
                           std::initializer_list<ByteSpan> parts, bool durable) {
  AtomicFile file(path, what);
  for (const ByteSpan part : parts) file.write(part);
  file.finish(durable);
  file.commit(durable);
}

}  // namespace rodend::results_detail

namespace rodend {

using namespace results_detail;

void write_text_file_atomically(const fs::path& path, const std::string& what,
                                const std::string& text, bool durable) {
  results_detail::write_file_atomically(path, what, {results_detail::bytes_of(text)}, durable);
}

WriteFailureInjection::WriteFailureInjection(long long bytes) {
  results_detail::g_write_budget.store(std::max(bytes, 0LL));
}
WriteFailureInjection::~WriteFailureInjection() {
  results_detail::g_write_budget.store(-1);
}

}  // namespace rodend
