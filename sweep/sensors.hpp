// Sensors: what an instrument would report of a signal (docs/sensors.md). A study's "sensors"
// block lists them by name; each reads one component of a signal of the accepted-step frames
// (kStepSignals), through an optional first- or second-order low-pass, sampled at its own rate,
// with white noise, a bias and a quantisation step; the noise is drawn from a seeded generator,
// so a case is reproducible. The low-pass is integrated exactly for the piecewise-linear
// interpolant of the step frames, so a sensor's record depends on the run's accepted steps and
// its own settings, never on time.sample_interval.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/params.hpp"
#include "core/scene.hpp"
#include "core/signals.hpp"

namespace rodend {

/// How a sensor setting's value is checked (the check column of sweep/sensor_settings.def).
enum class SensorCheck { signal, zero_to_two, finite, at_least_zero, above_zero };

/// One sensor, its values in the unit of the signal it reads: its name, then one member per key
/// of sweep/sensor_settings.def (with its default).
struct SensorSpec {
  std::string name;
#define RODEND_SENSOR_SETTING(key, type, check, unit, value, provenance, what, description) \
  type key = value;
#include "sweep/sensor_settings.def"
#undef RODEND_SENSOR_SETTING
  bool from_set = false;  ///< given by a named default set (left out where the scene lacks
                          ///< its signal)
};

/// The "sensors" block of a case.
struct SensorSettings {
  std::vector<SensorSpec> sensors;  ///< in the order they were named
  long long seed = 0;               ///< of the noise; each sensor draws from its own stream
  double noise_scale = 1.0;         ///< multiplies every sensor's noise_std
  std::string defaults;             ///< the named default set applied, "" for none
  bool empty() const { return sensors.empty(); }
};

/// The names of the default sets (sweep/sensor_sets.def).
std::vector<std::string> sensor_set_names();
/// The names of the sensors of default set `set`, in order (none for an unknown set).
std::vector<std::string> sensor_set_members(const std::string& set);
/// The keys of one sensor's object, in order (sweep/sensor_settings.def).
const std::vector<std::string>& sensor_keys();
/// Applies one key of the block: `field` is the path below "sensors." ("defaults", "seed",
/// "noise_scale", "<name>.<key>"), `key` the full path for messages. Throws InputError.
void apply_sensor_key(SensorSettings& s, const std::string& field, const Json& v,
                      const std::string& key);
/// The sensors `scene` records: those of a default set whose signal it lacks left out.
std::vector<SensorSpec> active_sensors(const SensorSettings& s, const Scene& scene);
/// Checks every sensor against the scene: its signal an accepted-step signal the scene
/// provides, the component within its width, the filter's cut-off set. InputError under
/// "sensors.<name>.".
void check_sensors(const SensorSettings& s, const Scene& scene);
/// The block in the canonical form of a case (entering its id); null when there are no sensors.
Json sensors_json(const SensorSettings& s);
/// The 64-bit seed of one sensor's stream: the block's seed, the sensor's name and the case's
/// point of a sampled design (`design_sample`, -1 without one: each point draws its own noise).
std::uint64_t sensor_seed(long long seed, const std::string& name, long design_sample = -1);

}  // namespace rodend
