// The strokes of the position command (kinds of core/scenes/input.hpp; menu motion_shapes.def):
// the actuator's extension-retraction cycle (thesis fig. 5.1), one class per stroke shape.
#pragma once

#include "core/scenes/input.hpp"

namespace rodend {

/// The timing and extent of a stroke cycle, `<prefix>.*`: per cycle an extension from the
/// retracted position to +extension over extension_time, a hold, a retraction to -retraction
/// over retraction_time, a hold; the first extension starts from 0 at start_time.
struct StrokeParams {
  double extension = 0.05;       ///< extended position [m]
  double retraction = 0.0;       ///< the retracted position is -retraction [m]
  double extension_time = 1.0;   ///< [s]
  double retraction_time = 1.0;  ///< [s]
  double hold_time = 0.2;        ///< hold after each stroke [s]
  double start_time = 0.0;       ///< [s]
  int cycles = 1;
  /// One cycle: extension, hold, retraction, hold [s].
  double period() const { return extension_time + retraction_time + 2.0 * hold_time; }
};

/// Reads extension, retraction, extension_time, retraction_time, hold_time, start_time and
/// cycles under the prefix. Throws InputError naming the key.
StrokeParams read_stroke_params(const InputKeys& in);

/// A stroke cycle x(t) of a normalised shape S(u), u in [0, 1] (S(0) = 0, S(1) = 1): each
/// stroke is from + (to - from) S(tau / its time).
class Stroke : public Input {
 public:
  explicit Stroke(const StrokeParams& s) : s_(s) {}
  Sample at(double t) const override;
  double end_time() const override { return s_.start_time + s_.cycles * s_.period(); }
  /// [-retraction, extension]: both shapes rise monotonically within a stroke.
  std::pair<double, double> range() const override { return {-s_.retraction, s_.extension}; }
  std::pair<std::string_view, std::string_view> range_keys() const override {
    return {"retraction", "extension"};
  }
  /// Cycles after the second repeat it (each starts from -retraction): two cycles, 20000
  /// samples each, cover the whole input.
  Scan scan() const override;
  const StrokeParams& params() const { return s_; }

 protected:
  /// S(u) and its first two derivatives.
  virtual void shape(double u, double& S, double& dS, double& ddS) const = 0;

 private:
  StrokeParams s_;
};

/// raised-cosine: S(u) = u - sin(2 pi u)/(2 pi), a smooth velocity pulse (thesis fig. 5.1).
class RaisedCosineStroke final : public Stroke {
 public:
  using Stroke::Stroke;
  static InputPtr read(const InputKeys& in);

 protected:
  void shape(double u, double& S, double& dS, double& ddS) const override;
};

/// minimum-jerk: S(u) = 10u^3 - 15u^4 + 6u^5.
class MinimumJerkStroke final : public Stroke {
 public:
  using Stroke::Stroke;
  static InputPtr read(const InputKeys& in);

 protected:
  void shape(double u, double& S, double& dS, double& ddS) const override;
};

/// step: the position jumps at the start of each stroke (a command only: it has no velocity).
class StepStroke final : public Stroke {
 public:
  using Stroke::Stroke;
  static InputPtr read(const InputKeys& in);

 protected:
  void shape(double u, double& S, double& dS, double& ddS) const override;
};

}  // namespace rodend
