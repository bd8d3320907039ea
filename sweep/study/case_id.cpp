// The case id: a case's canonical form (scene, parameters, signals, the settings of
// settings.def as their `id` column says) hashed with FNV-1a 64.
#include <cstdint>
#include <cstdio>

#include "sweep/study/loader.hpp"

namespace rodend {
using study_detail::write_settings;

std::string fnv1a64_hex(std::string_view text) {
  std::uint64_t h = 14695981039346656037ull;
  for (unsigned char c : text) {
    h ^= c;
    h *= 1099511628211ull;
  }
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(h));
  return buf;
}

namespace {

/// Numbers of parameters are physical quantities: 1 and 1.0 are the same value, so integers are
/// written as doubles in the canonical form.
Json as_doubles(const Json& j) {
  if (j.is_number()) return Json(j.get<double>());
  if (j.is_array()) {
    Json out = Json::array();
    for (const Json& e : j) out.push_back(as_doubles(e));
    return out;
  }
  if (j.is_object()) {
    Json out = Json::object();
    for (auto it = j.begin(); it != j.end(); ++it) out[it.key()] = as_doubles(*it);
    return out;
  }
  return j;
}

}  // namespace

Json CaseSpec::canonical() const {
  Json sig = Json::array();
  for (SignalId id : signals) sig.push_back(std::string(signal_spec(id).name));
  Json c = {
      {"scene", scene}, {"parameters", as_doubles(identity_values(parameters))}, {"signals", sig}};
  write_settings(*this, c);
  if (design_sample >= 0) c["design_sample"] = design_sample;
  if (!sensors.empty()) c["sensors"] = sensors_json(sensors);  // ids without sensors unchanged
  return c;
}

std::string case_id(const CaseSpec& c) {
  return fnv1a64_hex(c.canonical().dump());
}

}  // namespace rodend
