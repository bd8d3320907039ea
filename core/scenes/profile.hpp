// Profiles from data (issue 31 item 1): a position command or a hinge moment given as a time
// series from a file (a recorded flight, a rig sequence). The file is read once per study
// (sweep/profile.hpp) into an immutable ProfileData that every case naming it shares; a scene
// holds a ProfileInput: that data plus how to read between and past its samples.
#pragma once

#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/choice.hpp"
#include "core/params.hpp"
#include "core/profile_data.hpp"

namespace rodend {

/// How a profile is read between its samples (core/scenes/profile_interpolations.def):
///   linear: straight lines (the value is continuous, its rate steps at each sample)
///   pchip:  the monotone piecewise-cubic Hermite interpolant (Fritsch & Carlson 1980, slopes
///           by Brodlie's weighted harmonic mean as in MATLAB's and Boost's pchip): continuous
///           value and rate, no overshoot (it stays within each interval's two samples)
#define RODEND_CHOICE_ENUM ProfileInterpolation
#define RODEND_CHOICE_FILE "core/scenes/profile_interpolations.def"
#include "core/choice.hpp"

/// What a profile does past its last sample (core/scenes/profile_past_end.def):
///   error:  a run longer than the profile is refused when the study is loaded
///   hold:   the last value is held
///   repeat: the profile repeats with the period last time - first time
#define RODEND_CHOICE_ENUM ProfilePastEnd
#define RODEND_CHOICE_FILE "core/scenes/profile_past_end.def"
#include "core/choice.hpp"

/// Fills `d.slope` (pchip) from d.time and d.value (at least two samples, time increasing).
void compute_pchip_slopes(ProfileData& d);

/// A profile as a scene reads it.
struct ProfileInput {
  using Interpolation = ProfileInterpolation;
  using PastEnd = ProfilePastEnd;
  Interpolation interpolation = Interpolation::linear;
  PastEnd past_end = PastEnd::error;
  std::shared_ptr<const ProfileData> data;

  /// Value, rate and its rate at time t. Before the first sample the first value is held; past
  /// the last, `past_end` (error: the last value is held; the study refuses a run that would
  /// need it).
  struct Sample {
    double value, rate, acceleration;
  };
  Sample at(double t) const;
  /// The smallest and largest value (both interpolations stay within the samples' range).
  std::pair<double, double> range() const;
  /// The time of the last sample [s].
  double end_time() const { return data->end(); }
};

/// Reads `<prefix>.interpolation`, `<prefix>.past_end` and the data attached to `<prefix>.file`
/// (ParameterSet::attach, done by the study that loaded the parameters). Throws InputError
/// naming `<prefix>.file` when no data is attached.
ProfileInput read_profile_input(const ParameterSet& p, const std::string& prefix);

}  // namespace rodend
