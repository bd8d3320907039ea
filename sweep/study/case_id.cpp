// The case id: a case's canonical form (scene, parameters, signals, the settings of
// settings.def as their `id` column says) hashed with FNV-1a 64.
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <iterator>
#include <string_view>
#include <utility>

#include "core/contact.hpp"
#include "sweep/study/loader.hpp"

namespace rodend {
using study_detail::Grid;
using study_detail::write_settings;

namespace {

constexpr std::uint64_t kFnvOffset = 14695981039346656037ull;

std::uint64_t fnv1a64(std::uint64_t h, std::string_view text) {
  for (unsigned char c : text) {
    h ^= c;
    h *= 1099511628211ull;
  }
  return h;
}

}  // namespace

std::string fnv1a64_hex(std::string_view text) {
  const std::uint64_t h = fnv1a64(kFnvOffset, text);
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

/// Parameters added after results were stored, with the value that gives what came before (a
/// name from its catalogue, or a number): left out of the id at that value, so the ids of earlier
/// runs hold.
const std::pair<std::string_view, Json> kIdentityDefaults[] = {
    {"friction.mode", choice_name(FrictionMode::smooth)},  // the law as one function
    // the free body's loads took the waveforms' keys: at these values a sine load is the
    // A sin(2 pi f t) from t = 0 of before, and the chirps' keys are unused by the earlier kinds
    {"force.start_time", 0.0},
    {"force.cycles", 1e6},
    {"force.start_frequency", 0.5},
    {"force.end_frequency", 5.0},
    {"force.chirp_duration", 2.0},
    {"moment.start_time", 0.0},
    {"moment.cycles", 1e6},
    {"moment.start_frequency", 0.5},
    {"moment.end_frequency", 5.0},
    {"moment.chirp_duration", 2.0},
};

/// Whether a parameter is left out of the id at one of its values (a grid over it: no template).
bool left_out_at_default(const std::string& key) {
  return std::any_of(std::begin(kIdentityDefaults), std::end(kIdentityDefaults),
                     [&](const auto& d) { return d.first == key; });
}

Json parameter_identity(const ParameterSet& p) {
  Json values = as_doubles(identity_values(p));
  for (const auto& [key, value] : kIdentityDefaults) {
    const auto it = values.find(std::string(key));
    if (it != values.end() && *it == as_doubles(value)) values.erase(it);
  }
  return values;
}

}  // namespace

Json CaseSpec::canonical() const {
  Json sig = Json::array();
  for (SignalId id : signals) sig.push_back(std::string(signal_spec(id).name));
  Json c = {{"scene", scene}, {"parameters", parameter_identity(parameters)}, {"signals", sig}};
  write_settings(*this, c);
  if (design_sample >= 0) c["design_sample"] = design_sample;
  if (!sensors.empty()) c["sensors"] = sensors_json(sensors);  // ids without sensors unchanged
  return c;
}

std::string case_id(const CaseSpec& c) {
  return fnv1a64_hex(c.canonical().dump());
}

namespace study_detail {

std::optional<IdTemplate> IdTemplate::of(const Grid& g, const CaseSpec& base) {
  if (g.profiles_possible || g.scene_axis.axis >= 0 || g.bases.size() != 1) return std::nullopt;
  Json c = base.canonical();
  IdTemplate t;
  std::vector<std::pair<std::size_t, std::string>> marks;  // where, in the text, each slot
  for (std::size_t a = 0; a < g.axes.size(); ++a)
    for (std::size_t k = 0; k < g.axes[a].keys.size(); ++k) {
      const std::string& key = g.axes[a].keys[k];
      const std::string mark = "\x01rodend-slot-" + std::to_string(t.slots_.size()) + "\x01";
      if (key == "design.sample") {
        c["design_sample"] = mark;
      } else if (key.rfind("parameters.", 0) == 0 && c["parameters"].contains(key.substr(11)) &&
                 !left_out_at_default(key.substr(11))) {
        c["parameters"][key.substr(11)] = mark;
      } else {
        return std::nullopt;  // a setting (its form in the id varies), a key not in the id
      }
      t.slots_.push_back({a, k, key == "design.sample"});
      marks.emplace_back(0, Json(mark).dump());
    }
  const std::string text = c.dump();
  for (auto& [at, mark] : marks) {
    at = text.find(mark);
    if (at == std::string::npos || text.find(mark, at + 1) != std::string::npos)
      return std::nullopt;
  }
  std::vector<std::size_t> order(marks.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(),
            [&](std::size_t x, std::size_t y) { return marks[x].first < marks[y].first; });
  std::size_t from = 0;
  std::vector<Slot> slots;
  for (const std::size_t i : order) {
    t.pieces_.push_back(text.substr(from, marks[i].first - from));
    from = marks[i].first + marks[i].second.size();
    slots.push_back(t.slots_[i]);
  }
  t.pieces_.push_back(text.substr(from));
  t.slots_ = std::move(slots);
  t.prefix_hash_ = fnv1a64(kFnvOffset, t.pieces_[0]);
  return t;
}

std::uint64_t IdTemplate::id(const Grid& g, const std::vector<std::size_t>& pos) const {
  std::uint64_t h = prefix_hash_;  // the first piece's, the same for every case
  for (std::size_t i = 0; i < slots_.size(); ++i) {
    const Slot& s = slots_[i];
    const Json& v = g.axes[s.axis].values[s.member][pos[s.axis]];
    h = fnv1a64(h, s.integer ? Json(v.get<long>()).dump() : as_doubles(v).dump());
    h = fnv1a64(h, pieces_[i + 1]);
  }
  return h;
}

}  // namespace study_detail
}  // namespace rodend
