// The settings of the study sections, sweep/settings.def: the one list the reader
// (read_setting), the writer (write_settings: the canonical form), the schema and the docs
// table (study_fields) use.
#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <type_traits>
#include <variant>

#include "core/presets.hpp"
#include "sweep/study/loader.hpp"

namespace rodend {}  // namespace rodend

namespace rodend::study_detail {

namespace {

/// The checks settings.def names (see there).
namespace checks {
using Rule = Check::Rule;
Check rule(Rule r, double lo = 0.0, double hi = 0.0, std::string what = "",
           std::vector<std::string> choices = {}) {
  return {r, lo, hi, std::move(what), std::move(choices)};
}
template <class Names>
std::vector<std::string> strings(const Names& names) {
  return std::vector<std::string>(names.begin(), names.end());
}
Check validated_later() {
  return rule(Rule::later);
}
template <class Names>
Check validated_later(const Names& names) {
  return rule(Rule::later, 0.0, 0.0, "", strings(names));
}
Check validated_now() {
  return rule(Rule::now);
}
Check at_least(double lo) {
  return rule(Rule::at_least, lo);
}
Check above(double lo) {
  return rule(Rule::above, lo);
}
Check int_range(double lo, double hi, const char* what) {
  return rule(Rule::int_range, lo, hi, what);
}
template <class Names>
Check one_of(const Names& names) {
  return rule(Rule::one_of, 0.0, 0.0, "", strings(names));
}
}  // namespace checks

Setting make_setting(const char* section, const char* key, Kind kind, const char* unit, Check check,
                     InId id, const char* description, Member (*of_draft)(Draft&),
                     ConstMember (*of_case)(const CaseSpec&)) {
  const char* type = kind == Kind::number ? "number" : kind == Kind::integer ? "integer" : "string";
  StudyField info;
  info.section = section;
  info.name = key;
  info.type = type;
  info.unit = unit;
  info.description = description;
  info.choices = check.choices;
  using Rule = Check::Rule;
  auto bound = [&](double x) {
    return kind == Kind::integer ? Json(static_cast<long long>(x)) : Json(x);
  };
  if (check.rule == Rule::at_least || check.rule == Rule::above || check.rule == Rule::int_range)
    info.minimum = bound(check.lo);
  if (check.rule == Rule::int_range) info.maximum = bound(check.hi);
  info.exclusive_minimum = check.rule == Rule::above;
  return {std::move(info), std::move(check), id, of_draft, of_case};
}

}  // namespace

const std::vector<Setting>& settings() {
  using namespace checks;
  // clang-format off
  static const std::vector<Setting> kSettings{
#define RODEND_SETTING(SEC, KEY, KIND, UNIT, CHECK, ID, DESC)                       \
  make_setting(#SEC, #KEY, Kind::KIND, UNIT, CHECK, InId::ID, DESC,                 \
               [](Draft& d) -> Member { return &d.SEC.KEY; },                       \
               [](const CaseSpec& c) -> ConstMember { return &c.SEC.KEY; }),
#define RODEND_SPECIAL_SETTING(SEC, KEY, KIND, UNIT, CHECK, DESC) \
  make_setting(#SEC, #KEY, Kind::KIND, UNIT, CHECK, InId::special, DESC, nullptr, nullptr),
#include "sweep/settings.def"
#undef RODEND_SETTING
#undef RODEND_SPECIAL_SETTING
  };
  // clang-format on
  return kSettings;
}

const Setting* find_setting(std::string_view section, std::string_view name) {
  for (const Setting& s : settings())
    if (s.info.section == section && s.info.name == name) return &s;
  return nullptr;
}

std::vector<std::string> setting_names(std::string_view section) {
  std::vector<std::string> out;
  for (const Setting& s : settings())
    if (s.info.section == section) out.push_back(s.info.name);
  return out;
}

const std::vector<std::string>& case_sections() {
  static const std::vector<std::string> kSections = [] {
    std::vector<std::string> out{"parameters"};
    for (const Setting& s : settings())
      if (s.info.section != "output" &&
          std::find(out.begin(), out.end(), s.info.section) == out.end())
        out.push_back(s.info.section);
    return out;
  }();
  return kSections;
}

namespace {

std::string number_text(double x) {
  std::ostringstream o;
  o << x;
  return o.str();
}

// The reader: one overload per member type, each with the checks of its line.
void read_member(double& m, const Json& v, const std::string& key, const Check& c) {
  const double x = need_number(v, key);
  const bool open = c.rule == Check::Rule::above;
  if ((open || c.rule == Check::Rule::at_least) &&
      (!std::isfinite(x) || (open ? !(x > c.lo) : !(x >= c.lo))))
    throw InputError(key, std::string("expected a finite number ") + (open ? "> " : ">= ") +
                              number_text(c.lo) + ", got " + v.dump());
  m = x;
}
template <class Int>
requires std::is_integral_v<Int>
void read_member(Int& m, const Json& v, const std::string& key, const Check& c) {
  const long long n = need_integer(v, key);
  const bool ranged = c.rule == Check::Rule::int_range;
  const double lo = ranged ? c.lo : static_cast<double>(std::numeric_limits<Int>::min());
  const double hi = ranged ? c.hi : static_cast<double>(std::numeric_limits<Int>::max());
  if (static_cast<double>(n) < lo || static_cast<double>(n) > hi)
    throw InputError(key, "expected " + (ranged ? c.what : std::string("an integer")) + " from " +
                              number_text(lo) + " to " + number_text(hi) + ", got " + v.dump());
  m = static_cast<Int>(n);
}
std::string read_string(const Json& v, const std::string& key, const Check& c) {
  std::string s = need_string(v, key);
  if (c.rule == Check::Rule::one_of &&
      std::find(c.choices.begin(), c.choices.end(), s) == c.choices.end())
    throw InputError(key, "expected " + alternatives(c.choices, true) + ", got \"" + s + "\"");
  return s;
}
void read_member(std::string& m, const Json& v, const std::string& key, const Check& c) {
  m = read_string(v, key, c);
}
/// A choice of a catalogue (core/choice.hpp): its name, read into the enum.
template <Choice E>
void read_member(E& m, const Json& v, const std::string& key, const Check& c) {
  const std::string s = read_string(v, key, c);
  const auto e = choice_from_name<E>(s);
  if (!e)
    throw InputError(key, "unknown " + key.substr(key.rfind('.') + 1) + " '" + s +
                              "'; expected one of: " + choice_list<E>());
  m = *e;
}

/// validated_now(): the section's own validate(), as soon as one of its keys is set.
void validate_section(const Draft& d, const std::string& section) {
  if (section != "health")
    throw std::logic_error("settings.def: validated_now() has no validate() for " + section);
  validate(d.health);
}

}  // namespace

void read_setting(Draft& d, const Setting& s, const Json& v, const std::string& key) {
  if (!s.of_draft) {
    if (s.info.section == "integrator" && s.info.name == "preset") return read_preset(d, s, v, key);
    throw std::logic_error("settings.def: no reader for the special setting " + key);
  }
  std::visit([&](auto* m) { read_member(*m, v, key, s.check); }, s.of_draft(d));
  if (s.check.rule == Check::Rule::now) validate_section(d, s.info.section);
}

namespace {

// The writer: a member's value as JSON.
template <class T>
Json value_json(const T& x) {
  return Json(x);
}
template <Choice E>
Json value_json(const E& e) {
  return std::string(choice_name(e));
}
Json value_of(const Setting& s, const CaseSpec& c) {
  return std::visit([](const auto* m) { return value_json(*m); }, s.of_case(c));
}

}  // namespace

void write_settings(const CaseSpec& c, Json& out) {
  static const CaseSpec kDefaults{};
  for (const Setting& s : settings()) {
    if (s.id == InId::special || s.id == InId::not_in_id) continue;
    // only a wear evolution has them: the ids of ordinary cases do not change
    if (s.info.section == "wear_evolution" && !c.wear_evolution.enabled) continue;
    Json v = value_of(s, c);
    if (s.id == InId::in_id_as_double) v = v.get<double>();
    if (s.id != InId::in_id_if_not_default)
      out[s.info.section][s.info.name] = std::move(v);
    else if (v != value_of(s, kDefaults))
      out[s.info.name] = std::move(v);
  }
}

}  // namespace rodend::study_detail

namespace rodend {

using study_detail::Setting;
using study_detail::settings;
using study_detail::value_of;

std::vector<StudyField> study_fields() {
  // the defaults: of a default case, but for the integrator (a study's default is the scene's
  // balanced preset) and time (both keys are required)
  static const CaseSpec kDefaults{};
  std::vector<StudyField> out;
  for (const Setting& s : settings()) {
    out.push_back(s.info);
    if (s.of_case && s.info.section != "integrator" && s.info.section != "time")
      out.back().default_value = value_of(s, kDefaults);
  }
  return out;
}

}  // namespace rodend
