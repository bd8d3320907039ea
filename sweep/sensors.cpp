// The "sensors" block of a study: its keys read and checked, the default sets
// (sweep/sensor_sets.def), the sensors a scene records and the block's canonical form.
#include "sweep/sensors.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/errors.hpp"

namespace rodend {
namespace {

struct SetEntry {
  const char* set;
  SensorSpec spec;
};

const std::vector<SetEntry>& set_catalogue() {
  static const std::vector<SetEntry> entries{
#define RODEND_SENSOR(set, name, signal, comp, noise, bias, quant, order, cutoff, rate, note) \
  {#set, SensorSpec{#name, signal, comp, noise, bias, quant, order, cutoff, rate, true}},
#include "sweep/sensor_sets.def"
#undef RODEND_SENSOR
  };
  return entries;
}

std::string quoted_list(const std::vector<std::string>& names) {
  std::string out;
  for (std::size_t i = 0; i < names.size(); ++i)
    out += (i == 0 ? "" : i + 1 == names.size() ? " or " : ", ") + ("\"" + names[i] + "\"");
  return out;
}

double finite_number(const Json& v, const std::string& key) {
  if (!v.is_number() || !std::isfinite(v.get<double>()))
    throw InputError(key, "expected a finite number; got " + v.dump());
  return v.get<double>();
}

long long whole_number(const Json& v, const std::string& key, long long lo, long long hi) {
  if (!v.is_number_integer() || v.get<long long>() < lo || v.get<long long>() > hi)
    throw InputError(key, "expected an integer from " + std::to_string(lo) + " to " +
                              std::to_string(hi) + "; got " + v.dump());
  return v.get<long long>();
}

double at_least_zero(const Json& v, const std::string& key, const char* what) {
  const double x = finite_number(v, key);
  if (x < 0.0) throw InputError(key, std::string("expected ") + what + " >= 0; got " + v.dump());
  return x;
}

double above_zero(const Json& v, const std::string& key, const char* what) {
  const double x = finite_number(v, key);
  if (!(x > 0.0)) throw InputError(key, std::string("expected ") + what + " > 0; got " + v.dump());
  return x;
}

SensorSpec& sensor_named(SensorSettings& s, const std::string& name, const std::string& key) {
  const bool ok = !name.empty() && std::all_of(name.begin(), name.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_';
  });
  if (!ok)
    throw InputError(key, "expected a sensor name of lower-case letters, digits and '_', or " +
                              quoted_list({"defaults", "seed", "noise_scale"}));
  for (SensorSpec& x : s.sensors)
    if (x.name == name) return x;
  s.sensors.push_back(SensorSpec{});
  s.sensors.back().name = name;
  return s.sensors.back();
}

void apply_defaults(SensorSettings& s, const Json& v, const std::string& key) {
  const std::vector<std::string> names = sensor_set_names();
  if (!v.is_string() || std::find(names.begin(), names.end(), v.get<std::string>()) == names.end())
    throw InputError(key,
                     "expected a default sensor set, " + quoted_list(names) + "; got " + v.dump());
  s.defaults = v.get<std::string>();
  for (const SetEntry& e : set_catalogue())
    if (s.defaults == e.set) sensor_named(s, e.spec.name, key) = e.spec;
}

void read_setting(std::string& out, const Json& v, const std::string& key, SensorCheck,
                  const char* what) {
  if (!v.is_string()) throw InputError(key, std::string("expected ") + what);
  out = v.get<std::string>();
}

void read_setting(int& out, const Json& v, const std::string& key, SensorCheck, const char*) {
  out = static_cast<int>(whole_number(v, key, 0, 2));
}

void read_setting(double& out, const Json& v, const std::string& key, SensorCheck c,
                  const char* what) {
  if (c == SensorCheck::at_least_zero) out = at_least_zero(v, key, what);
  if (c == SensorCheck::above_zero) out = above_zero(v, key, what);
  if (c == SensorCheck::finite) out = finite_number(v, key);
}

/// One key of a sensor's object, by the catalogue sweep/sensor_settings.def.
void apply_sensor_field(SensorSpec& x, const std::string& k, const Json& v,
                        const std::string& key) {
#define RODEND_SENSOR_SETTING(name, type, check, unit, value, provenance, what, description) \
  if (k == #name) return read_setting(x.name, v, key, SensorCheck::check, what);
#include "sweep/sensor_settings.def"
#undef RODEND_SENSOR_SETTING
  throw InputError(key, "unknown sensor key; expected one of " + quoted_list(sensor_keys()));
}

/// A setting as the canonical form writes it (numbers as numbers, whole ones too).
Json canonical(const std::string& v) {
  return v;
}
Json canonical(double v) {
  return v;
}
Json canonical(int v) {
  return static_cast<double>(v);
}

}  // namespace

std::vector<std::string> sensor_set_names() {
  std::vector<std::string> out;
  for (const SetEntry& e : set_catalogue())
    if (std::find(out.begin(), out.end(), e.set) == out.end()) out.push_back(e.set);
  return out;
}

std::vector<std::string> sensor_set_members(const std::string& set) {
  std::vector<std::string> out;
  for (const SetEntry& e : set_catalogue())
    if (set == e.set) out.push_back(e.spec.name);
  return out;
}

const std::vector<std::string>& sensor_keys() {
  static const std::vector<std::string> keys{
#define RODEND_SENSOR_SETTING(key, ...) #key,
#include "sweep/sensor_settings.def"
#undef RODEND_SENSOR_SETTING
  };
  return keys;
}

void apply_sensor_key(SensorSettings& s, const std::string& field, const Json& v,
                      const std::string& key) {
  if (field == "defaults") return apply_defaults(s, v, key);
  if (field == "seed") {
    s.seed = whole_number(v, key, 0, std::numeric_limits<long long>::max());
    return;
  }
  if (field == "noise_scale") {
    s.noise_scale = at_least_zero(v, key, "a factor on every noise_std");
    return;
  }
  const auto dot = field.find('.');
  if (dot == std::string::npos)
    throw InputError(key, "expected an object of sensor keys (" + quoted_list(sensor_keys()) +
                              "), \"defaults\", \"seed\" or \"noise_scale\"");
  // a sensor the study names itself must find its signal; one of a default set keeps being
  // optional when the study changes a key of it (a noise level on a grid axis)
  SensorSpec& x = sensor_named(s, field.substr(0, dot), key);
  apply_sensor_field(x, field.substr(dot + 1), v, key);
}

std::vector<SensorSpec> active_sensors(const SensorSettings& s, const Scene& scene) {
  const auto sig = scene.signals();
  std::vector<SensorSpec> out;
  for (const SensorSpec& x : s.sensors) {
    const auto id = signal_by_name(x.signal);
    const bool has = id && std::find(sig.begin(), sig.end(), *id) != sig.end();
    if (has || !x.from_set) out.push_back(x);
  }
  return out;
}

void check_sensors(const SensorSettings& s, const Scene& scene) {
  const auto sig = scene.signals();
  std::vector<std::string> readable;  // the step signals of this scene
  for (SignalId id : kStepSignals)
    if (id != SignalId::time && std::find(sig.begin(), sig.end(), id) != sig.end())
      readable.emplace_back(signal_spec(id).name);
  for (const SensorSpec& x : active_sensors(s, scene)) {
    const std::string at = "sensors." + x.name + ".";
    if (std::find(readable.begin(), readable.end(), x.signal) == readable.end())
      throw InputError(at + "signal",
                       (x.signal.empty() ? std::string("missing") : "'" + x.signal + "'") +
                           ": expected a signal this scene provides on every accepted step, " +
                           quoted_list(readable));
    const int width = signal_spec(*signal_by_name(x.signal)).width;
    if (x.component >= width)
      throw InputError(at + "component", "expected a component from 0 to " +
                                             std::to_string(width - 1) + " of " + x.signal);
    if (!(x.rate > 0.0)) throw InputError(at + "rate", "missing: the sampling rate [Hz]");
    if (x.filter_order > 0 && !(x.cutoff > 0.0))
      throw InputError(at + "cutoff", "missing: the low-pass's cut-off [Hz] (filter_order " +
                                          std::to_string(x.filter_order) + ")");
  }
}

Json sensors_json(const SensorSettings& s) {
  if (s.empty()) return nullptr;
  Json list = Json::object();
  for (const SensorSpec& x : s.sensors) {
    Json& entry = list[x.name];
#define RODEND_SENSOR_SETTING(key, ...) entry[#key] = canonical(x.key);
#include "sweep/sensor_settings.def"
#undef RODEND_SENSOR_SETTING
    if (x.filter_order == 0) entry["cutoff"] = 0.0;  // no filter: its cut-off does not matter
  }
  return {{"sensors", list}, {"seed", std::to_string(s.seed)}, {"noise_scale", s.noise_scale}};
}

std::uint64_t sensor_seed(long long seed, const std::string& name, long design_sample) {
  std::uint64_t h = 14695981039346656037ull;  // FNV-1a 64 of the name, then the seed mixed in
  for (unsigned char c : name) h = (h ^ c) * 1099511628211ull;
  std::uint64_t z = h ^ (static_cast<std::uint64_t>(seed) + 0x9e3779b97f4a7c15ull);
  z ^= static_cast<std::uint64_t>(design_sample + 1) * 0xd1b54a32d192ed03ull;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;  // splitmix64's finaliser
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  return z ^ (z >> 31);
}

}  // namespace rodend
