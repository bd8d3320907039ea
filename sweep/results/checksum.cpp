// The checksum header of the results files (sweep/results/checksum.hpp): written and verified.
#include "sweep/results/checksum.hpp"

#include <fcntl.h>
#include <libdeflate.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <mutex>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "sweep/results.hpp"

namespace rodend::results_detail {

std::array<unsigned char, kUserBlock> checksum_header(std::uint32_t crc, std::size_t file_size) {
  std::array<unsigned char, kUserBlock> header{};
  std::snprintf(reinterpret_cast<char*>(header.data()), header.size(), "%scrc32 %08x\nbytes %zu\n",
                std::string(kChecksumMagic).c_str(), static_cast<unsigned>(crc), file_size);
  return header;
}
std::array<unsigned char, kUserBlock> checksum_header(ByteSpan image) {
  if (image.size() < sizeof kHdf5Signature ||
      std::memcmp(image.data(), kHdf5Signature, sizeof kHdf5Signature) != 0)
    throw std::logic_error("the HDF5 image of a case file does not start with its superblock");
  return checksum_header(libdeflate_crc32(0, image.data(), image.size()),
                         static_cast<std::size_t>(kUserBlock) + image.size());
}
namespace {

/// Reads `n` bytes at `offset` of `fd` into `buf`; throws naming `path` (CorruptFile `corrupt`
/// when the file ends before them).
void read_exactly(int fd, unsigned char* buf, std::size_t offset, std::size_t n,
                  const fs::path& path, const std::string& corrupt) {
  std::size_t got = 0;
  while (got < n) {
    const ssize_t r = ::pread(fd, buf + got, n - got, static_cast<off_t>(offset + got));
    if (r < 0 && errno == EINTR) continue;
    if (r < 0)
      throw std::runtime_error("cannot read " + path.string() + ": " + std::strerror(errno));
    if (r == 0) throw CorruptFile(corrupt + "shorter than it was a moment ago");
    got += static_cast<std::size_t>(r);
  }
}

/// The checksum of a case file or summary.h5 (`kind`: "case file", "summary file"): its user
/// block must be exactly the header checksum_header writes (every byte of the 512, padding
/// included), its size the one stated, the CRC-32 of the rest the one stated. False for a
/// file without a user block (an HDF5 file written before checksums). Throws CorruptFile.
bool verify_checksum(const fs::path& path, const std::string& kind) {
  const std::string corrupt = "corrupt " + kind + " " + path.string() + ": ";
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);
  if (fd < 0)
    throw std::runtime_error("cannot read " + kind + " " + path.string() + ": " +
                             std::strerror(errno));
  struct FdCloser {
    int fd;
    ~FdCloser() { ::close(fd); }
  } closer{fd};
  struct stat st {};
  if (::fstat(fd, &st) != 0)
    throw std::runtime_error("cannot read " + kind + " " + path.string() + ": " +
                             std::strerror(errno));
  if (!S_ISREG(st.st_mode))
    throw std::runtime_error("cannot read " + kind + " " + path.string() + ": not a regular file");
  const auto size = static_cast<std::size_t>(st.st_size);
  std::vector<unsigned char> buf(std::size_t{1} << 20);
  const std::size_t head = std::min<std::size_t>(size, kUserBlock);
  read_exactly(fd, buf.data(), 0, head, path, corrupt);
  if (head >= sizeof kHdf5Signature &&
      std::memcmp(buf.data(), kHdf5Signature, sizeof kHdf5Signature) == 0)
    return false;  // no user block: written before checksums (HDF5 checks what it can)
  if (head < kChecksumMagic.size() ||
      std::memcmp(buf.data(), kChecksumMagic.data(), kChecksumMagic.size()) != 0)
    throw CorruptFile(corrupt + (size == 0 ? "empty file"
                                           : "no checksum header (\"RODEND-CHECKSUM\") and not an "
                                             "HDF5 file"));
  const std::string header(reinterpret_cast<const char*>(buf.data()), head);
  unsigned stored = 0;
  unsigned long long bytes = 0;
  if (head < kUserBlock ||
      std::sscanf(header.c_str() + kChecksumMagic.size(), "crc32 %8x\nbytes %llu", &stored,
                  &bytes) != 2 ||
      std::memcmp(buf.data(), checksum_header(stored, bytes).data(), kUserBlock) != 0)
    throw CorruptFile(corrupt + "damaged checksum header");
  if (bytes != size)
    throw CorruptFile(corrupt + std::to_string(size) + " bytes, its checksum header says " +
                      std::to_string(bytes) + " (truncated or extended)");
  std::uint32_t crc = 0;
  for (std::size_t offset = kUserBlock; offset < size;) {
    const std::size_t n = std::min(buf.size(), size - offset);
    read_exactly(fd, buf.data(), offset, n, path, corrupt);
    crc = libdeflate_crc32(crc, buf.data(), n);
    offset += n;
  }
  if (crc != stored) {
    char text[96];
    std::snprintf(text, sizeof text,
                  "content does not match its checksum (CRC-32 %08x, stored %08x)",
                  static_cast<unsigned>(crc), stored);
    throw CorruptFile(corrupt + text);
  }
  return true;
}

}  // namespace

void verify_case_file_once(const fs::path& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) {
    verify_case_file(path);  // reports why it cannot be read
    return;
  }
  using Key = std::array<long long, 7>;
  const Key key{static_cast<long long>(st.st_dev),
                static_cast<long long>(st.st_ino),
                static_cast<long long>(st.st_size),
                st.st_mtim.tv_sec,
                st.st_mtim.tv_nsec,
                st.st_ctim.tv_sec,
                st.st_ctim.tv_nsec};
  static std::mutex mutex;
  static std::set<Key> verified;
  {
    const std::lock_guard lock(mutex);
    if (verified.count(key)) return;
  }
  verify_case_file(path);
  const std::lock_guard lock(mutex);
  if (verified.size() >= 4096) verified.clear();  // memory that does not grow with the cases
  verified.insert(key);
}

}  // namespace rodend::results_detail

namespace rodend {

using namespace results_detail;

bool verify_case_file(const fs::path& path) {
  try {
    return verify_checksum(path, "case file");
  } catch (const CorruptFile& e) {
    throw CorruptCaseFile(e.what());
  }
}

bool verify_summary_file(const fs::path& path) {
  return verify_checksum(path, "summary file");
}

}  // namespace rodend
