// The record spool (RecordSpool, sweep/results.hpp): the rows of the summary kept on the disk.
//
// A record on the spool: its size (uint32), then the fields of sweep/case_record.def in
// catalogue order (numbers as 8 bytes, native; text, and json and features as their text, as
// its size (uint32) and bytes), then the metric count and the metrics (8 bytes each). The file is
// private to the process (native byte order; nothing else reads it).
#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <cstring>
#include <map>
#include <mutex>
#include <stdexcept>

#include "sweep/results.hpp"
#include "sweep/results/atomic_file.hpp"

namespace rodend {
namespace {

using namespace results_detail;

/// The grid keys to which `r` gives a value that is not a number.
std::vector<std::string> text_coordinate_keys(const CaseRecord& r) {
  std::vector<std::string> keys;
  if (!r.coordinates.is_object()) return keys;
  for (const auto& [key, value] : r.coordinates.items())
    if (!value.is_number()) keys.push_back(key);
  return keys;
}

template <class T>
void put_raw(std::string& out, const T& v) {
  out.append(reinterpret_cast<const char*>(&v), sizeof v);
}
void put_text(std::string& out, const std::string& s) {
  put_raw(out, static_cast<std::uint32_t>(s.size()));
  out += s;
}

/// Reads what put_raw / put_text wrote; throws on a record shorter than it says.
class SpoolReader {
 public:
  SpoolReader(const char* p, std::size_t n) : p_(p), end_(p + n) {}
  template <class T>
  T raw() {
    T v;
    take(&v, sizeof v);
    return v;
  }
  std::string text() {
    const auto n = raw<std::uint32_t>();
    if (static_cast<std::size_t>(end_ - p_) < n) throw std::runtime_error("truncated record");
    std::string s(p_, n);
    p_ += n;
    return s;
  }

 private:
  void take(void* v, std::size_t n) {
    if (static_cast<std::size_t>(end_ - p_) < n) throw std::runtime_error("truncated record");
    std::memcpy(v, p_, n);
    p_ += n;
  }
  const char* p_;
  const char* end_;
};

/// One field of the case record on the spool (sweep/case_record.def): numbers as 8 bytes,
/// text (json and features as their text) as its size and bytes.
void put_field(std::string& out, const record_text& v) {
  put_text(out, v);
}
void put_field(std::string& out, record_integer v) {
  put_raw(out, static_cast<std::int64_t>(v));
}
void put_field(std::string& out, record_real v) {
  put_raw(out, v);
}
template <class T>
void put_field(std::string& out, const T& v) {
  put_text(out, record_field_text(v));
}

void get_field(SpoolReader& in, record_text& v) {
  v = in.text();
}
void get_field(SpoolReader& in, record_integer& v) {
  v = in.raw<std::int64_t>();
}
void get_field(SpoolReader& in, record_real& v) {
  v = in.raw<double>();
}
template <class T>
void get_field(SpoolReader& in, T& v) {
  record_field_from_text(in.text(), v);
}

}  // namespace

std::string encode_record(const CaseRecord& r) {
  std::string out;
  put_raw(out, std::uint32_t{0});  // the size, set below
  for_each_record_field(r, [&](const RecordFieldSpec&, const auto& v) { put_field(out, v); });
  put_raw(out, static_cast<std::uint32_t>(r.metrics.size()));
  out.append(reinterpret_cast<const char*>(r.metrics.data()), sizeof(double) * r.metrics.size());
  const auto size = static_cast<std::uint32_t>(out.size());
  std::memcpy(out.data(), &size, sizeof size);
  return out;
}

CaseRecord decode_record(const char* p, std::size_t n) {
  SpoolReader in(p, n);
  (void)in.raw<std::uint32_t>();
  CaseRecord r;
  for_each_record_field(r, [&](const RecordFieldSpec&, auto& v) { get_field(in, v); });
  if (in.raw<std::uint32_t>() != r.metrics.size()) throw std::runtime_error("metric count");
  for (double& m : r.metrics) m = in.raw<double>();
  return r;
}

struct RecordSpool::Impl {
  fs::path summary;  ///< dir/summary.h5, named in messages (the spool is the summary's rows)
  int fd = -1;
  mutable std::mutex mutex;
  std::vector<std::int64_t> offsets;  ///< per slot: the record's offset, -1 when none
  std::string buffer;                 ///< records not yet written, from offset `written`
  std::int64_t written = 0;           ///< bytes in the file
  /// grid key -> records (as they stand) that give it a value that is not a number
  std::map<std::string, std::size_t> text_keys;
  std::size_t count = 0, failed = 0;  ///< records; of them, not "ok"
  /// where read() is: `cursor_slot` is the slot of row `cursor_row` (reads in order walk the
  /// offsets once; reset by put)
  mutable std::size_t cursor_row = 0, cursor_slot = 0;

  static constexpr std::size_t kBufferBytes = 1 << 16;

  /// Writes the buffer out; call with `mutex` held.
  void flush() {
    if (buffer.empty()) return;
    if (const int err = write_all(fd, reinterpret_cast<const unsigned char*>(buffer.data()),
                                  buffer.size(), static_cast<off_t>(written));
        err != 0)
      throw std::runtime_error("cannot write summary file " + summary.string() +
                               ": write error on its rows' spool in " +
                               summary.parent_path().string() + ": " + std::strerror(err));
    written += static_cast<std::int64_t>(buffer.size());
    buffer.clear();
  }
  /// The record at `offset`; call with `mutex` held.
  CaseRecord load(std::int64_t offset) const {
    if (offset >= written) {  // still in the buffer
      const std::size_t at = static_cast<std::size_t>(offset - written);
      std::uint32_t size = 0;
      std::memcpy(&size, buffer.data() + at, sizeof size);
      return decode_record(buffer.data() + at, size);
    }
    std::uint32_t size = 0;
    std::string bytes(sizeof size, '\0');
    read_at(bytes.data(), sizeof size, offset);
    std::memcpy(&size, bytes.data(), sizeof size);
    bytes.resize(size);
    read_at(bytes.data(), size, offset);
    return decode_record(bytes.data(), size);
  }
  void read_at(char* out, std::size_t n, std::int64_t offset) const {
    while (n > 0) {
      const ssize_t r = ::pread(fd, out, n, static_cast<off_t>(offset));
      if (r < 0 && errno == EINTR) continue;
      if (r <= 0)
        throw std::runtime_error("cannot read the rows' spool of " + summary.string() + ": " +
                                 (r < 0 ? std::strerror(errno) : "unexpected end"));
      out += r;
      n -= static_cast<std::size_t>(r);
      offset += r;
    }
  }
};

RecordSpool::RecordSpool(const fs::path& dir, std::size_t slots) : impl_(std::make_unique<Impl>()) {
  impl_->summary = dir / "summary.h5";
  const fs::path path = temp_path_for(dir / "summary-rows");
  impl_->fd = ::open(path.c_str(), O_RDWR | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0600);
  if (impl_->fd < 0)
    throw std::runtime_error("cannot write summary file " + impl_->summary.string() +
                             ": cannot create its rows' spool " + path.string() + ": " +
                             std::strerror(errno));
  ::unlink(path.c_str());  // anonymous from now on (left behind, a later run removes it)
  impl_->offsets.assign(slots, -1);
}

RecordSpool::~RecordSpool() {
  if (impl_ && impl_->fd >= 0) ::close(impl_->fd);
}

void RecordSpool::put(std::size_t slot, const CaseRecord& record) {
  const std::string bytes = encode_record(record);
  std::lock_guard lock(impl_->mutex);
  if (slot >= impl_->offsets.size()) throw std::out_of_range("spool slot");
  if (impl_->offsets[slot] < 0) {
    ++impl_->count;
  } else {  // replaced: what the old record counted no longer holds
    const CaseRecord old = impl_->load(impl_->offsets[slot]);
    if (old.status != RunStatus::ok) --impl_->failed;
    for (const std::string& k : text_coordinate_keys(old))
      if (--impl_->text_keys[k] == 0) impl_->text_keys.erase(k);
  }
  if (impl_->buffer.size() + bytes.size() > Impl::kBufferBytes) impl_->flush();
  impl_->offsets[slot] = impl_->written + static_cast<std::int64_t>(impl_->buffer.size());
  if (record.status != RunStatus::ok) ++impl_->failed;
  impl_->buffer += bytes;
  for (const std::string& k : text_coordinate_keys(record)) ++impl_->text_keys[k];
  impl_->cursor_row = impl_->cursor_slot = 0;
}

std::size_t RecordSpool::failed() const {
  std::lock_guard lock(impl_->mutex);
  return impl_->failed;
}

std::size_t RecordSpool::size() const {
  std::lock_guard lock(impl_->mutex);
  return impl_->count;
}

void RecordSpool::read(std::size_t begin, std::size_t end, std::vector<CaseRecord>& out) const {
  std::lock_guard lock(impl_->mutex);
  if (begin > end || end > impl_->count) throw std::out_of_range("spool rows");
  Impl& m = *impl_;
  if (begin < m.cursor_row) m.cursor_row = m.cursor_slot = 0;
  out.clear();
  for (std::size_t row = begin; row < end; ++row) {
    // to the slot of `row`: the next slot with a record, `row - cursor_row` times over
    for (;; ++m.cursor_slot) {
      while (m.offsets[m.cursor_slot] < 0) ++m.cursor_slot;
      if (m.cursor_row == row) break;
      ++m.cursor_row;
    }
    out.push_back(m.load(m.offsets[m.cursor_slot]));
  }
}

std::set<std::string> RecordSpool::text_coordinates() const {
  std::lock_guard lock(impl_->mutex);
  std::set<std::string> keys;
  for (const auto& [key, n] : impl_->text_keys) keys.insert(key);
  return keys;
}

}  // namespace rodend
