// Recorded signals: the catalogue (signals.def) as an enum, a table and a frame.
#pragma once

#include <array>
#include <cassert>
#include <cstddef>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

#include "core/math.hpp"

namespace rodend {

enum class SignalId : int {
#define RODEND_SIGNAL(id, unit, width, doc) id,
#include "core/signals.def"
#undef RODEND_SIGNAL
  count_
};

inline constexpr int signal_count = static_cast<int>(SignalId::count_);

/// One row of the catalogue.
struct SignalSpec {
  std::string_view name;
  std::string_view unit;
  int width;
  std::string_view description;
};

namespace detail {
// In the header, so that the lookups of every sample and step (SignalFrame::set and get, the
// observer's copies) inline to a table read: out of line they cost 50 M instructions of a
// 1,206 M thesis cycle at 1e-4 s samples.
inline constexpr std::array<SignalSpec, signal_count> kSignalCatalogue{{
#define RODEND_SIGNAL(id, unit, width, doc) SignalSpec{#id, unit, width, doc},
#include "core/signals.def"
#undef RODEND_SIGNAL
}};
constexpr std::array<int, signal_count + 1> make_signal_offsets() {
  std::array<int, signal_count + 1> o{};
  for (int i = 0; i < signal_count; ++i) o[i + 1] = o[i] + kSignalCatalogue[i].width;
  return o;
}
inline constexpr auto kSignalOffsets = make_signal_offsets();
}  // namespace detail

/// The whole catalogue, in declaration order.
inline std::span<const SignalSpec> signal_catalogue() {
  return detail::kSignalCatalogue;
}
inline const SignalSpec& signal_spec(SignalId id) {
  return detail::kSignalCatalogue[static_cast<std::size_t>(id)];
}
std::optional<SignalId> signal_by_name(std::string_view name);
/// Offset of a signal in a SignalFrame.
inline int signal_offset(SignalId id) {
  return detail::kSignalOffsets[static_cast<std::size_t>(id)];
}
/// Total width of a SignalFrame.
inline int signal_frame_width() {
  return detail::kSignalOffsets[signal_count];
}

/// Values of every catalogue signal at one instant; a scene writes the ones it provides.
class SignalFrame {
 public:
  SignalFrame() : values_(static_cast<std::size_t>(signal_frame_width()), 0.0) {}
  void set(SignalId id, double v) {
    assert(signal_spec(id).width == 1);
    values_[static_cast<std::size_t>(signal_offset(id))] = v;
  }
  void set(SignalId id, const Vec3& v) {
    assert(signal_spec(id).width == 3);
    const auto o = static_cast<std::size_t>(signal_offset(id));
    values_[o] = v.x();
    values_[o + 1] = v.y();
    values_[o + 2] = v.z();
  }
  void set(SignalId id, double a, double b) {
    assert(signal_spec(id).width == 2);
    const auto o = static_cast<std::size_t>(signal_offset(id));
    values_[o] = a;
    values_[o + 1] = b;
  }
  /// One component of a signal of any width.
  void set_component(SignalId id, int component, double v) {
    assert(component >= 0 && component < signal_spec(id).width);
    values_[static_cast<std::size_t>(signal_offset(id) + component)] = v;
  }
  double get(SignalId id, int component = 0) const {
    return values_[static_cast<std::size_t>(signal_offset(id) + component)];
  }
  Vec3 get3(SignalId id) const { return Vec3(get(id, 0), get(id, 1), get(id, 2)); }
  const double* data(SignalId id) const { return values_.data() + signal_offset(id); }
  /// Whether every value of the frame is finite (x * 0 is 0 for a finite x, NaN otherwise).
  bool all_finite() const {
    double probe = 0.0;
    for (const double v : values_) probe += v * 0.0;
    return probe == 0.0;
  }
  /// Whether the values at `slots` (offsets into the frame) are finite: a frame's own signals,
  /// not the whole catalogue's width.
  bool all_finite(std::span<const int> slots) const {
    double probe = 0.0;
    for (const int i : slots) probe += values_[static_cast<std::size_t>(i)] * 0.0;
    return probe == 0.0;
  }

 private:
  std::vector<double> values_;
};

}  // namespace rodend
