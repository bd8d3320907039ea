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

/// The whole catalogue, in declaration order.
std::span<const SignalSpec> signal_catalogue();
const SignalSpec& signal_spec(SignalId id);
std::optional<SignalId> signal_by_name(std::string_view name);
/// Offset of a signal in a SignalFrame.
int signal_offset(SignalId id);
/// Total width of a SignalFrame.
int signal_frame_width();

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
  double get(SignalId id, int component = 0) const {
    return values_[static_cast<std::size_t>(signal_offset(id) + component)];
  }
  Vec3 get3(SignalId id) const { return Vec3(get(id, 0), get(id, 1), get(id, 2)); }
  const double* data(SignalId id) const { return values_.data() + signal_offset(id); }

 private:
  std::vector<double> values_;
};

}  // namespace rodend
