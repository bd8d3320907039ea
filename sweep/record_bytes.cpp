#include "sweep/record_bytes.hpp"

#include <cstdint>
#include <cstring>
#include <stdexcept>

namespace rodend {

namespace {

template <class T>
void put(std::string& out, T v) {
  char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));
  out.append(b, sizeof(T));
}

void put_text(std::string& out, const std::string& s) {
  put<std::uint32_t>(out, static_cast<std::uint32_t>(s.size()));
  out += s;
}

template <class T>
T take(std::string_view& in) {
  if (in.size() < sizeof(T)) throw std::runtime_error("a case record message is truncated");
  T v;
  std::memcpy(&v, in.data(), sizeof(T));
  in.remove_prefix(sizeof(T));
  return v;
}

std::string take_text(std::string_view& in) {
  const auto n = take<std::uint32_t>(in);
  if (in.size() < n) throw std::runtime_error("a case record message is truncated");
  std::string s(in.substr(0, n));
  in.remove_prefix(n);
  return s;
}

}  // namespace

void pack_record(std::size_t slot, const CaseRecord& rec, std::string& out) {
  put<std::uint64_t>(out, slot);
  put_text(out, rec.id);
  put_text(out, rec.status);
  put_text(out, rec.message);
  put<double>(out, rec.t_reached);
  put<double>(out, rec.wall_time);
  put<std::int64_t>(out, rec.steps_accepted);
  put<std::int64_t>(out, rec.steps_rejected);
  put<std::int64_t>(out, rec.rhs_calls);
  put_text(out, rec.started_utc);
  put_text(out, rec.finished_utc);
  put<std::uint32_t>(out, static_cast<std::uint32_t>(rec.metrics.size()));
  for (const double m : rec.metrics) put<double>(out, m);
}

std::size_t unpack_record(std::string_view& in, CaseRecord& rec) {
  const auto slot = static_cast<std::size_t>(take<std::uint64_t>(in));
  rec.id = take_text(in);
  rec.status = take_text(in);
  rec.message = take_text(in);
  rec.t_reached = take<double>(in);
  rec.wall_time = take<double>(in);
  rec.steps_accepted = take<std::int64_t>(in);
  rec.steps_rejected = take<std::int64_t>(in);
  rec.rhs_calls = take<std::int64_t>(in);
  rec.started_utc = take_text(in);
  rec.finished_utc = take_text(in);
  if (take<std::uint32_t>(in) != rec.metrics.size())
    throw std::runtime_error("a case record message has another metric count than this build");
  for (double& m : rec.metrics) m = take<double>(in);
  return slot;
}

}  // namespace rodend
