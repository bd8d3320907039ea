#include "sweep/study.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <fstream>
#include <functional>
#include <limits>
#include <mutex>
#include <optional>
#include <sstream>
#include <type_traits>
#include <variant>

#include "core/json_text.hpp"
#include "core/presets.hpp"
#include "core/scene.hpp"
#include "sweep/profile.hpp"

namespace rodend {
namespace fs = std::filesystem;

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

std::string_view to_string(HistoryPrecision p) {
  return p == HistoryPrecision::float32 ? "float32" : "float64";
}

std::vector<std::string_view> history_precisions() {
  return {to_string(HistoryPrecision::float64), to_string(HistoryPrecision::float32)};
}

namespace {

/// Limits on what a study may ask for (README "Studies"): cases per study, nesting of the
/// document, memory of one case's histories.
constexpr std::size_t kMaxCases = kMaxStudyCases;
constexpr std::size_t kMaxDepth = 64;
constexpr double kMaxHistoryBytes = 2147483648.0;  // 2 GiB

/// Nesting depth of a document, without recursion (a deeply nested input must not overflow the
/// stack here, nor later in the recursive copies and dumps this file makes of it).
std::size_t nesting_depth(const Json& doc) {
  std::size_t deepest = 0;
  std::vector<std::pair<const Json*, std::size_t>> todo{{&doc, 1}};
  while (!todo.empty()) {
    const auto [j, d] = todo.back();
    todo.pop_back();
    deepest = std::max(deepest, d);
    if (d > kMaxDepth) break;
    if (j->is_structured())
      for (const Json& child : *j) todo.emplace_back(&child, d + 1);
  }
  return deepest;
}

double need_number(const Json& v, const std::string& key) {
  if (!v.is_number()) throw InputError(key, "expected a number, got " + json_type_name(v));
  return v.get<double>();
}
long long need_integer(const Json& v, const std::string& key) {
  if (!v.is_number()) throw InputError(key, "expected an integer, got " + json_type_name(v));
  const double d = v.get<double>();
  if (d != std::floor(d)) throw InputError(key, "expected an integer, got " + v.dump());
  if (std::abs(d) > 9e18)
    throw InputError(key, "expected an integer of magnitude at most 9e18, got " + v.dump());
  return static_cast<long long>(d);
}
std::string need_string(const Json& v, const std::string& key) {
  if (!v.is_string()) throw InputError(key, "expected a string, got " + json_type_name(v));
  return v.get<std::string>();
}
const Json& need_object(const Json& v, const std::string& key) {
  if (!v.is_object()) throw InputError(key, "expected an object, got " + json_type_name(v));
  return v;
}

/// A path the study names for its results: not empty (NUL characters are refused before).
fs::path output_path(const Json& v, const std::string& key) {
  const std::string s = need_string(v, key);
  if (s.empty())
    throw InputError(key,
                     "expected a non-empty directory path (or no \"output\" key: "
                     "results/<name>)");
  return fs::path(s);
}

/// A case being resolved: the draft every setting is applied to.
struct Draft {
  std::string scene;
  ParameterSet parameters;
  IntegratorSettings integrator;
  TimeSettings time;
  HealthLimits health;
  MetricsSettings metrics;
  WearEvolutionSettings wear_evolution;
  /// the study's storage settings: read with the same reader (parse_output), never per case
  OutputSettings output;
  /// scene-axis studies: a parameter key this case's scene does not have is skipped (the study
  /// checks that some scene of it has the key)
  bool skip_absent_parameters = false;
};

/// Where a study's values came from, for the parameters' provenance (ParameterSet::set): the
/// study file and the key paths --set gave (each with its "key=value" text; the last wins).
struct Origins {
  std::string file;
  std::vector<std::pair<std::string, std::string>> set;

  /// The --set text that gave `key` or a section holding it ("parameters", "grid"), or "".
  std::string set_text(const std::string& key) const {
    for (auto it = set.rbegin(); it != set.rend(); ++it)
      if (key == it->first || key.rfind(it->first + ".", 0) == 0) return it->second;
    return "";
  }
  /// A study-level value at `key` ("parameters.contact.clearance").
  std::pair<std::string, std::string> of_study(const std::string& key) const {
    const std::string by_set = set_text(key);
    if (!by_set.empty()) return {"set", "--set " + by_set};
    return {"study", key + " in " + file};
  }
  /// A grid or design value at `key`, from the axis at `where` ("grid[0]", "design.factors[1]").
  std::pair<std::string, std::string> of_axis(const std::string& where) const {
    const std::string section = where.substr(0, where.find_first_of(".["));
    const std::string by_set = set_text(section);
    return {section == "design" ? "design" : "grid",
            where + " in " + file + (by_set.empty() ? "" : " (as --set " + by_set + ")")};
  }
};

// --- the settings of the sections: sweep/settings.def ------------------------------------

/// What a setting's value must be beyond its JSON type (the `check` column of settings.def).
struct Check {
  enum class Rule { later, now, at_least, above, int_range, one_of };
  Rule rule = Rule::later;
  double lo = 0.0, hi = 0.0;
  std::string what;                  ///< int_range: what the integer is ("a deflate level")
  std::vector<std::string> choices;  ///< the allowed strings (one_of; later: for the schema)
};

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

/// How a setting enters the canonical form (the `id` column of settings.def).
enum class InId { in_id, in_id_as_double, not_in_id, in_id_if_not_default, special };
/// The `kind` column: the JSON type of the value.
enum class Kind { number, integer, string, choice };

/// The member a setting is, of a draft (read) or of a resolved case (written).
using Member = std::variant<double*, int*, long*, long long*, std::string*, HistoryPrecision*,
                            IntegratorMethod*, ContactOnset*>;
using ConstMember =
    std::variant<const double*, const int*, const long*, const long long*, const std::string*,
                 const HistoryPrecision*, const IntegratorMethod*, const ContactOnset*>;

/// One line of settings.def.
struct Setting {
  StudyField info;
  Check check;
  InId id = InId::special;
  Member (*of_draft)(Draft&) = nullptr;  ///< null: a special setting, read by explicit code
  ConstMember (*of_case)(const CaseSpec&) = nullptr;
};

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

/// Every line of settings.def, in its order: the one list the reader (apply, parse_output),
/// the writer (CaseSpec::canonical), the schema and the docs table (study_fields) use.
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

/// The setting `section`.`name`, or null.
const Setting* find_setting(std::string_view section, std::string_view name) {
  for (const Setting& s : settings())
    if (s.info.section == section && s.info.name == name) return &s;
  return nullptr;
}

/// "a, b or c" (quoted: "\"a\", \"b\" or \"c\"").
std::string alternatives(const std::vector<std::string>& names, bool quoted,
                         const char* last = " or ") {
  std::string out;
  for (std::size_t i = 0; i < names.size(); ++i) {
    if (i > 0) out += i + 1 == names.size() ? last : ", ";
    out += quoted ? "\"" + names[i] + "\"" : names[i];
  }
  return out;
}

/// The names of the settings of a section, in settings.def order.
std::vector<std::string> setting_names(std::string_view section) {
  std::vector<std::string> out;
  for (const Setting& s : settings())
    if (s.info.section == section) out.push_back(s.info.name);
  return out;
}

/// The sections a case is resolved from (the keys a grid axis or --set may address):
/// parameters and every section of settings.def but output, which is the study's.
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
void read_member(HistoryPrecision& m, const Json& v, const std::string& key, const Check& c) {
  const std::string s = read_string(v, key, c);
  for (const HistoryPrecision p : {HistoryPrecision::float64, HistoryPrecision::float32})
    if (to_string(p) == s) m = p;
}

/// validated_now(): the section's own validate(), as soon as one of its keys is set.
void validate_section(const Draft& d, const std::string& section) {
  if (section != "health")
    throw std::logic_error("settings.def: validated_now() has no validate() for " + section);
  validate(d.health);
}

/// integrator.preset (special in settings.def): a whole IntegratorSettings, the scene's own.
void read_preset(Draft& d, const Setting& s, const Json& v, const std::string& key) {
  const std::string name = need_string(v, key);
  const auto p = preset_settings(d.scene, name);
  if (!p)
    throw InputError(
        key, "unknown preset '" + name + "'; expected " + alternatives(s.check.choices, false));
  d.integrator = *p;
}

/// Sets one setting of a draft (the reader settings.def generates); `key` is its full path.
void read_setting(Draft& d, const Setting& s, const Json& v, const std::string& key) {
  if (!s.of_draft) {
    if (s.info.section == "integrator" && s.info.name == "preset") return read_preset(d, s, v, key);
    throw std::logic_error("settings.def: no reader for the special setting " + key);
  }
  std::visit([&](auto* m) { read_member(*m, v, key, s.check); }, s.of_draft(d));
  if (s.check.rule == Check::Rule::now) validate_section(d, s.info.section);
}

// The writer: a member's value as JSON.
template <class T>
Json value_json(const T& x) {
  return Json(x);
}
template <Choice E>
Json value_json(const E& e) {
  return std::string(choice_name(e));
}
Json value_json(HistoryPrecision p) {
  return std::string(to_string(p));
}
Json value_of(const Setting& s, const CaseSpec& c) {
  return std::visit([](const auto* m) { return value_json(*m); }, s.of_case(c));
}

/// The settings of a case in its canonical form, added to `out` (settings.def, column id).
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

/// The "output" key: the results directory as a string, or an object of the output settings
/// of settings.def (directory, compression_level, history_precision).
void parse_output(const Json& v, Study& study) {
  if (v.is_string()) {
    study.output_dir = output_path(v, "output");
    return;
  }
  const std::vector<std::string> names = setting_names("output");
  if (!v.is_object())
    throw InputError("output", "expected the results directory (a string) or an object with " +
                                   alternatives(names, false) + "; got " + json_type_name(v));
  Draft d;
  d.output = study.output;
  for (auto it = v.begin(); it != v.end(); ++it) {
    const std::string key = "output." + it.key();
    const Setting* s = find_setting("output", it.key());
    if (!s) throw InputError(key, "unknown key; expected " + alternatives(names, false));
    if (it.key() == "directory")  // special in settings.def: the study's path, no setting
      study.output_dir = output_path(*it, key);
    else
      read_setting(d, *s, *it, key);
  }
  study.output = d.output;
}

/// Applies one setting addressed by a full key path (parameters.*, or a section of
/// settings.def but output). Throws InputError with that key path. `from`: where the value
/// came from (source, note), recorded in a parameter's provenance.
void apply(Draft& d, const std::string& key, const Json& v,
           const std::pair<std::string, std::string>& from = {}) {
  const auto dot = key.find('.');
  const std::string section = key.substr(0, dot);
  const std::string field = dot == std::string::npos ? "" : key.substr(dot + 1);
  if (field.empty())
    throw InputError(key, "expected a key path such as parameters.contact.clearance");
  if (section == "parameters") {
    if (d.skip_absent_parameters && !d.parameters.has(field)) return;
    try {
      d.parameters.set(field, v, from.first, from.second);
    } catch (const InputError& e) {
      throw e.located("", "parameters");
    }
    return;
  }
  const std::vector<std::string>& sections = case_sections();
  if (std::find(sections.begin(), sections.end(), section) == sections.end())
    throw InputError(
        key, "unknown section '" + section + "'; expected " + alternatives(sections, false));
  if (section == "wear_evolution") d.wear_evolution.enabled = true;
  const Setting* s = find_setting(section, field);
  if (!s) {
    std::string names;
    for (const std::string& n : setting_names(section)) names += (names.empty() ? "" : ", ") + n;
    throw InputError(key, "unknown " + section + " setting; expected one of " + names);
  }
  read_setting(d, *s, v, key);
}

/// A case's histories are held in memory until its file is written: refuse sizes that cannot be.
void check_history_size(const TimeSettings& t, const std::vector<SignalId>& signals) {
  double width = 0.0;
  for (SignalId id : signals) width += signal_spec(id).width;
  const double samples = std::floor(t.end / t.sample_interval + 1e-9) + 1.0;
  const double bytes = samples * width * 8.0;
  if (bytes > kMaxHistoryBytes) {
    std::ostringstream m;
    m << samples << " samples of " << width << " recorded values need " << bytes / 1073741824.0
      << " GiB of memory per case (limit 2 GiB); expected a larger sample interval, a shorter "
         "end time or fewer signals";
    throw InputError("time.sample_interval", m.str());
  }
}

/// Builds the scene to run its own physical checks; its key paths are under "parameters.".
std::unique_ptr<Scene> build_checked(const std::string& scene, const ParameterSet& params) {
  try {
    return make_scene(scene, params);
  } catch (const InputError& e) {
    if (e.key_path() == "scene") throw;
    throw e.located("", "parameters");
  }
}

/// Flattens {"contact": {"clearance": 1e-4}} into {"contact.clearance": 1e-4}; dotted keys pass.
void flatten(const Json& node, const std::string& prefix,
             std::vector<std::pair<std::string, Json>>& out) {
  for (auto it = node.begin(); it != node.end(); ++it) {
    const std::string key = prefix.empty() ? it.key() : prefix + "." + it.key();
    if (it->is_object())
      flatten(*it, key, out);
    else
      out.emplace_back(key, *it);
  }
}

/// Applies a section object ("integrator": {...}) as settings under that section.
void apply_section(Draft& d, const Json& doc, const std::string& section, const Origins& origins) {
  if (!doc.contains(section)) return;
  const Json& obj = need_object(doc[section], section);
  std::vector<std::pair<std::string, Json>> flat;
  flatten(obj, section, flat);
  // {"contact.clearance": a, "contact": {"clearance": b}} names one setting twice
  {
    std::vector<std::string> keys;
    for (const auto& kv : flat) keys.push_back(kv.first);
    std::sort(keys.begin(), keys.end());
    if (const auto dup = std::adjacent_find(keys.begin(), keys.end()); dup != keys.end())
      throw InputError(*dup,
                       "set twice (once as a dotted key, once nested); expected each setting "
                       "once");
  }
  // a preset sets every integrator field: apply it first, so the keys beside it override it
  std::stable_partition(flat.begin(), flat.end(),
                        [](const auto& kv) { return kv.first == "integrator.preset"; });
  for (const auto& [k, v] : flat) apply(d, k, v, origins.of_study(k));
}

struct Axis {
  std::vector<std::string> keys;          // several for a zip group
  std::vector<std::string> wheres;        // per key, its place in the study ("grid[0].zip[1]")
  std::vector<std::vector<Json>> values;  // per key, same length
  std::size_t size() const { return values.empty() ? 0 : values.front().size(); }
};

std::vector<Json> expand_values(const Json& a, const std::string& where) {
  std::vector<Json> out;
  const int forms = a.contains("values") + a.contains("linspace") + a.contains("logspace");
  if (forms != 1)
    throw InputError(where, "expected exactly one of \"values\", \"linspace\" or \"logspace\"");
  if (a.contains("values")) {
    const Json& v = a["values"];
    if (!v.is_array() || v.empty())
      throw InputError(where + ".values", "expected a non-empty array");
    for (const Json& e : v) out.push_back(e);
    return out;
  }
  const bool log = a.contains("logspace");
  const std::string key = where + (log ? ".logspace" : ".linspace");
  const Json& g = a[log ? "logspace" : "linspace"];
  if (!g.is_array() || g.size() != 3) throw InputError(key, "expected [start, stop, count]");
  const double start = need_number(g[0], key + "[0]");
  const double stop = need_number(g[1], key + "[1]");
  const long long n = need_integer(g[2], key + "[2]");
  if (n < 1 || n > static_cast<long long>(kMaxCases))
    throw InputError(key + "[2]", "expected a count in [1, 1e7]");
  if (log && !(start > 0.0 && stop > 0.0))
    throw InputError(key, "expected start > 0 and stop > 0 (the values, not exponents)");
  for (long long i = 0; i < n; ++i) {
    const double f = n == 1 ? 0.0 : static_cast<double>(i) / static_cast<double>(n - 1);
    double v = log ? std::exp(std::log(start) + f * (std::log(stop) - std::log(start)))
                   : start + f * (stop - start);
    if (i == n - 1) v = stop;  // end points exact
    if (i == 0) v = start;
    if (!std::isfinite(v))
      throw InputError(key,
                       "generates a value that is not a finite number; expected finite "
                       "start and stop");
    out.emplace_back(v);
  }
  return out;
}

Axis parse_axis(const Json& a, const std::string& where) {
  need_object(a, where);
  Axis axis;
  if (a.contains("zip")) {
    for (auto it = a.begin(); it != a.end(); ++it)
      if (it.key() != "zip") throw InputError(where + "." + it.key(), "unknown key in a zip group");
    const Json& members = a["zip"];
    if (!members.is_array() || members.empty())
      throw InputError(where + ".zip", "expected a non-empty array of axes");
    for (std::size_t i = 0; i < members.size(); ++i) {
      const std::string w = where + ".zip[" + std::to_string(i) + "]";
      if (members[i].is_object() && members[i].contains("zip"))
        throw InputError(w, "a zip group cannot contain another zip");
      Axis m = parse_axis(members[i], w);
      if (!axis.keys.empty() && m.size() != axis.size())
        throw InputError(w, "zip members must have the same length: " + std::to_string(m.size()) +
                                " vs " + std::to_string(axis.size()));
      axis.keys.push_back(m.keys[0]);
      axis.wheres.push_back(m.wheres[0]);
      axis.values.push_back(m.values[0]);
    }
    return axis;
  }
  for (auto it = a.begin(); it != a.end(); ++it)
    if (it.key() != "key" && it.key() != "values" && it.key() != "linspace" &&
        it.key() != "logspace")
      throw InputError(where + "." + it.key(),
                       "unknown key in a grid axis; expected key with values, linspace or "
                       "logspace, or zip");
  if (!a.contains("key"))
    throw InputError(where + ".key", "missing: the key path this axis varies");
  axis.keys.push_back(need_string(a["key"], where + ".key"));
  if (axis.keys.back().empty())
    throw InputError(where + ".key", "expected a key path such as parameters.contact.clearance");
  axis.wheres.push_back(where);
  axis.values.push_back(expand_values(a, where));
  return axis;
}

std::pair<std::size_t, std::size_t> line_column(const std::string& text, std::size_t byte) {
  std::size_t line = 1, col = 1;
  for (std::size_t i = 0; i < byte && i < text.size(); ++i) {
    if (text[i] == '\n') {
      ++line;
      col = 1;
    } else {
      ++col;
    }
  }
  return {line, col};
}

/// Key path of the first string or key holding a NUL character (escaped as \u0000), or none.
/// A NUL would cut a path or a message short where the string meets a C interface.
std::optional<std::string> find_nul(const Json& doc) {
  std::vector<std::pair<const Json*, std::string>> todo{{&doc, ""}};
  while (!todo.empty()) {
    const auto [j, path] = todo.back();
    todo.pop_back();
    if (j->is_string() && j->get_ref<const std::string&>().find('\0') != std::string::npos)
      return path;
    if (j->is_object()) {
      for (auto it = j->begin(); it != j->end(); ++it) {
        const std::string p = path.empty() ? it.key() : path + "." + it.key();
        if (it.key().find('\0') != std::string::npos) return p;
        todo.emplace_back(&*it, p);
      }
    } else if (j->is_array()) {
      for (std::size_t i = 0; i < j->size(); ++i)
        todo.emplace_back(&(*j)[i], path + "[" + std::to_string(i) + "]");
    }
  }
  return std::nullopt;
}

/// The design's points as an axis: "design.sample" (the point's index) zipped with each factor's
/// values.
Axis design_axis(const Design& design) {
  Axis axis;
  const std::size_t n = design.points(), d = design.dims();
  axis.keys.push_back("design.sample");
  axis.wheres.push_back("design");
  axis.values.emplace_back();
  for (std::size_t p = 0; p < n; ++p) axis.values.back().emplace_back(static_cast<long>(p));
  for (std::size_t j = 0; j < d; ++j) {
    axis.keys.push_back(design.factors[j].key);
    axis.wheres.push_back(design.factors[j].where);
    std::vector<Json> column;
    column.reserve(n);
    for (std::size_t p = 0; p < n; ++p) column.emplace_back(design.values[p * d + j]);
    axis.values.push_back(std::move(column));
  }
  return axis;
}

/// Every sampled parameter is a parameter of some scene of the study (a typo is caught at its
/// place in the design).
void check_design_keys(const Design& design, const std::vector<std::string>& scenes) {
  for (const DesignFactor& f : design.factors) {
    if (f.key.rfind("parameters.", 0) != 0) continue;  // settings: checked by apply()
    const std::string path = f.key.substr(11);
    if (std::none_of(scenes.begin(), scenes.end(), [&](const std::string& scene) {
          return ParameterSet::defaults_for(scene).has(path);
        }))
      throw InputError(f.where + ".key", "no scene of this study has parameter '" + path +
                                             "' (see `rodend params SCENE`)");
  }
}

/// Each design factor's SI unit: the parameter's (from the first scene that has it) or the
/// setting's.
std::vector<std::string> design_units(const Design& design,
                                      const std::vector<std::string>& scenes) {
  std::vector<std::string> units;
  for (const DesignFactor& f : design.factors) {
    std::string unit;
    if (f.key.rfind("parameters.", 0) == 0) {
      for (const std::string& scene : scenes) {
        const ParameterSet p = ParameterSet::defaults_for(scene);
        if (p.has(f.key.substr(11))) {
          unit = p.unit(f.key.substr(11));
          break;
        }
      }
    } else {
      const auto dot = f.key.find('.');
      if (const Setting* s = find_setting(f.key.substr(0, dot), f.key.substr(dot + 1)))
        unit = s->info.unit;
    }
    units.push_back(unit);
  }
  return units;
}

}  // namespace

Json CaseSpec::canonical() const {
  Json sig = Json::array();
  for (SignalId id : signals) sig.push_back(std::string(signal_spec(id).name));
  Json c = {
      {"scene", scene}, {"parameters", as_doubles(identity_values(parameters))}, {"signals", sig}};
  write_settings(*this, c);
  if (design_sample >= 0) c["design_sample"] = design_sample;
  return c;
}

std::string case_id(const CaseSpec& c) {
  return fnv1a64_hex(c.canonical().dump());
}

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

const std::vector<std::string>& study_keys() {
  static const std::vector<std::string> keys{
      "name",   "description", "scene", "parameters", "integrator",     "time",  "signals",
      "health", "metrics",     "grid",  "output",     "wear_evolution", "design"};
  return keys;
}

namespace {

// --- the loader's stages (parse_study) ----------------------------------------------------

/// The document as a whole: an object, nested a few levels, no NUL, only study keys.
void check_document(const Json& doc) {
  if (!doc.is_object()) throw InputError("", "a study must be a JSON object");
  if (nesting_depth(doc) > kMaxDepth)
    throw InputError("", "the document is nested deeper than " + std::to_string(kMaxDepth) +
                             " levels; a study needs a few");
  if (const auto nul = find_nul(doc))
    throw InputError(*nul, "a string with a NUL character (\\u0000); expected text without NUL");
  const std::vector<std::string>& keys = study_keys();
  for (auto it = doc.begin(); it != doc.end(); ++it)
    if (std::find(keys.begin(), keys.end(), it.key()) == keys.end())
      throw InputError(it.key(), "unknown key; expected one of " + alternatives(keys, false));
}

/// Name, description and where the results go.
void read_identity(Study& study, const Json& doc, const fs::path& file,
                   const fs::path& results_root) {
  study.file = file;
  study.source = doc;
  study.name = doc.contains("name") ? need_string(doc["name"], "name") : file.stem().string();
  if (study.name.empty() || study.name.find('/') != std::string::npos || study.name == "." ||
      study.name == "..")
    throw InputError("name", "expected a non-empty name without '/'");
  study.description =
      doc.contains("description") ? need_string(doc["description"], "description") : "";
  study.output_dir = results_root / study.name;
  study.results_root = results_root;
  if (doc.contains("output")) parse_output(doc["output"], study);
}

/// The grid's axes, each a single key or a zip group (cartesian product, last axis fastest),
/// then a sampled design's points as one more axis, the last.
std::vector<Axis> read_axes(Study& study, const Json& doc) {
  std::vector<Axis> axes;
  if (doc.contains("grid")) {
    const Json& g = doc["grid"];
    if (!g.is_array()) throw InputError("grid", "expected an array of axes");
    for (std::size_t i = 0; i < g.size(); ++i)
      axes.push_back(parse_axis(g[i], "grid[" + std::to_string(i) + "]"));
  }
  if (doc.contains("design")) {
    std::size_t grid_points = 1;
    for (const Axis& a : axes) grid_points *= std::max<std::size_t>(a.size(), 1);
    auto design = std::make_shared<Design>(
        parse_design(doc["design"], kMaxCases / std::max<std::size_t>(grid_points, 1)));
    axes.push_back(design_axis(*design));
    study.design = std::move(design);
  }
  return axes;
}

/// Where the grid's "scene" axis is, if it has one.
struct SceneAxis {
  std::ptrdiff_t axis = -1;  // index into the axes, -1 without a scene axis
  std::size_t member = 0;    // its key's place in a zip group
};

SceneAxis find_scene_axis(const std::vector<Axis>& axes) {
  for (std::size_t a = 0; a < axes.size(); ++a)
    for (std::size_t k = 0; k < axes[a].keys.size(); ++k)
      if (axes[a].keys[k] == "scene") return {static_cast<std::ptrdiff_t>(a), k};
  return {};
}

/// The scenes: the "scene" key, or the values of the grid axis "scene", in order of first use.
void read_scenes(Study& study, const Json& doc, const std::vector<Axis>& axes, SceneAxis sa) {
  if (sa.axis < 0) {
    if (!doc.contains("scene"))
      throw InputError("scene", "missing: which scene to run (or a grid axis \"scene\")");
    study.scene = need_string(doc["scene"], "scene");
    study.scenes = {study.scene};
    return;
  }
  const Axis& axis = axes[static_cast<std::size_t>(sa.axis)];
  if (doc.contains("scene"))
    throw InputError("scene", "the scene is also a grid axis (" + axis.wheres[sa.member] +
                                  "): give it in one place");
  const auto& values = axis.values[sa.member];
  for (std::size_t j = 0; j < values.size(); ++j) {
    const std::string where = axis.wheres[sa.member] + ".values[" + std::to_string(j) + "]";
    const std::string name = need_string(values[j], where);
    try {
      (void)ParameterSet::defaults_for(name);
    } catch (const InputError& e) {
      throw InputError(where, e.problem());
    }
    if (std::find(study.scenes.begin(), study.scenes.end(), name) == study.scenes.end())
      study.scenes.push_back(name);
  }
}

std::string scene_list(const Study& study) {
  std::string out;
  for (const std::string& n : study.scenes) out += (out.empty() ? "" : ", ") + n;
  return out;
}

/// With a scene axis, a parameter key (study level or grid) applies where the case's scene has
/// it; one that no scene of the study has is an error (a typo).
void check_scene_axis_keys(const Study& study, const Json& doc, const std::vector<Axis>& axes) {
  std::vector<ParameterSet> defaults;
  for (const std::string& n : study.scenes) defaults.push_back(ParameterSet::defaults_for(n));
  auto check_known = [&](const std::string& path, const std::string& where) {
    if (std::none_of(defaults.begin(), defaults.end(),
                     [&](const ParameterSet& p) { return p.has(path); }))
      throw InputError(where, "no scene of this study (" + scene_list(study) + ") has parameter '" +
                                  path + "' (see `rodend params SCENE`)");
  };
  if (doc.contains("parameters")) {
    std::vector<std::pair<std::string, Json>> flat;
    flatten(need_object(doc["parameters"], "parameters"), "", flat);
    for (const auto& [k, v] : flat) check_known(k, "parameters." + k);
  }
  for (const Axis& a : axes)
    for (std::size_t k = 0; k < a.keys.size(); ++k)
      if (a.keys[k].rfind("parameters.", 0) == 0)
        check_known(a.keys[k].substr(11), a.wheres[k] + ".key");
}

/// The recorded signals: "all" (default) or a list of names.
struct SignalSelection {
  Json names;
  bool all = true;
  std::vector<bool> provided;  // per listed name: some scene of the study records it
};

SignalSelection read_signal_selection(const Json& doc) {
  SignalSelection s;
  s.names = doc.contains("signals") ? doc["signals"] : Json("all");
  s.all = s.names.is_string() && s.names.get<std::string>() == "all";
  if (!s.all && !s.names.is_array())
    throw InputError("signals", "expected \"all\" or an array of signal names");
  s.provided.assign(s.all ? 0 : s.names.size(), false);
  return s;
}

/// The signals a scene records of the selection, in catalogue order, time first.
std::vector<SignalId> scene_signals(const Scene& scene, SignalSelection& sel, const Study& study,
                                    bool several) {
  const auto provided = scene.signals();
  if (sel.all) return {provided.begin(), provided.end()};
  std::vector<SignalId> signals{SignalId::time};
  for (std::size_t i = 0; i < sel.names.size(); ++i) {
    const std::string key = "signals[" + std::to_string(i) + "]";
    const std::string sname = need_string(sel.names[i], key);
    const auto id = signal_by_name(sname);
    if (!id) throw InputError(key, "unknown signal '" + sname + "' (see `rodend signals`)");
    if (std::find(provided.begin(), provided.end(), *id) == provided.end()) {
      if (!several)
        throw InputError(key, "signal '" + sname + "' is not recorded by scene " + study.scene);
      continue;
    }
    sel.provided[i] = true;
    if (std::find(signals.begin(), signals.end(), *id) == signals.end()) signals.push_back(*id);
  }
  std::sort(signals.begin(), signals.end());
  return signals;
}

/// A scene's own error in a study of several scenes names the scene.
[[noreturn]] void rethrow_for_scene(const InputError& e, const std::string& name, bool several) {
  if (!several) throw e;
  throw InputError(e.key_path(), e.problem() + " (scene " + name + ")");
}

/// The base draft of one scene: its defaults and balanced preset, then the study's sections.
Draft base_draft(const std::string& name, const Json& doc, bool several, const Origins& origins) {
  Draft base;
  base.scene = name;
  base.skip_absent_parameters = several;
  base.parameters = ParameterSet::defaults_for(name);        // unknown scene -> key "scene"
  base.integrator = *preset_settings(name, kDefaultPreset);  // overridden below
  try {
    for (const std::string& section : case_sections()) apply_section(base, doc, section, origins);
  } catch (const InputError& e) {
    rethrow_for_scene(e, name, several);
  }
  if (!doc["time"].contains("end")) throw InputError("time.end", "missing: the end time [s]");
  if (!doc["time"].contains("sample_interval"))
    throw InputError("time.sample_interval", "missing: the history sample interval [s]");
  return base;
}

/// What rebuilds a case from its grid index (issue 16 item 6): the base draft and signals of
/// each scene, the axes, and one 64-bit id per case once validated.
struct Grid {
  std::vector<Axis> axes;
  SceneAxis scene_axis;
  std::vector<std::string> scenes;
  std::vector<Draft> bases;
  std::vector<std::vector<SignalId>> scene_signals;
  OutputSettings output;
  std::vector<std::uint64_t> ids;          // filled by the validation pass
  Origins origins;                         // the parameters' provenance
  std::shared_ptr<ProfileStore> profiles;  // the profile files, each read once (sweep/profile.hpp)
  bool profiles_possible = true;           // some case may use one (else their lookup is skipped)
};

/// Each scene's base draft and recorded signals; a scene's own error names it when the study
/// has several.
void build_bases(Grid& grid, const Study& study, const Json& doc, bool several) {
  SignalSelection sel = read_signal_selection(doc);
  for (const std::string& name : study.scenes) {
    Draft base = base_draft(name, doc, several, grid.origins);
    std::unique_ptr<Scene> scene;  // the scene's signal list needs a built scene
    try {
      attach_profiles(base.parameters, *grid.profiles);
      scene = build_checked(name, base.parameters);
    } catch (const InputError& e) {
      rethrow_for_scene(e, name, several);
    }
    grid.scene_signals.push_back(scene_signals(*scene, sel, study, several));
    grid.bases.push_back(std::move(base));
  }
  for (std::size_t i = 0; i < sel.provided.size(); ++i)
    if (!sel.provided[i])
      throw InputError("signals[" + std::to_string(i) + "]",
                       "signal '" + sel.names[i].get<std::string>() +
                           "' is recorded by no scene of this study (" + scene_list(study) + ")");
}

/// The coordinate keys, each on one axis, and the number of cases (at most kMaxCases).
std::size_t count_cases(Study& study, const std::vector<Axis>& axes) {
  std::size_t total = 1;
  for (const Axis& a : axes) {
    for (const std::string& k : a.keys) {
      if (std::find(study.axis_keys.begin(), study.axis_keys.end(), k) != study.axis_keys.end())
        throw InputError("grid", "key '" + k + "' appears on more than one axis");
      study.axis_keys.push_back(k);
    }
    total *= a.size();
    if (total > kMaxCases)
      throw InputError("grid",
                       "more than 1e7 cases, the limit of a study (each case is "
                       "validated before anything runs): split the study into several");
  }
  return total;
}

/// A preset sets every integrator field, so a preset axis would silently override any other
/// integrator setting of the study (the summary would then show a method the case did not
/// run): refuse the combination.
void check_preset_axis(const Study& study, const Json& doc) {
  const auto& keys = study.axis_keys;
  if (std::find(keys.begin(), keys.end(), "integrator.preset") == keys.end()) return;
  for (const std::string& k : keys)
    if (k != "integrator.preset" && k.rfind("integrator.", 0) == 0)
      throw InputError("grid", "axes integrator.preset and " + k +
                                   " contradict each other (a preset sets every integrator "
                                   "field); expected one of them");
  if (doc.contains("integrator"))
    for (auto it = doc["integrator"].begin(); it != doc["integrator"].end(); ++it)
      if (it.key() != "preset")
        throw InputError("integrator." + it.key(),
                         "set beside a grid axis integrator.preset, which sets every "
                         "integrator field; expected the preset axis alone, or the "
                         "setting as an axis without presets");
}

/// Each axis's position for case `index` (last axis fastest) and the case's scene.
std::vector<std::size_t> grid_position(const Grid& g, std::size_t index, std::size_t& which) {
  std::size_t rest = index;
  std::vector<std::size_t> pos(g.axes.size());
  for (std::size_t a = g.axes.size(); a-- > 0;) {
    pos[a] = rest % g.axes[a].size();
    rest /= g.axes[a].size();
  }
  which = 0;  // the case's scene, an index into g.scenes
  if (g.scene_axis.axis >= 0) {
    const auto sa = static_cast<std::size_t>(g.scene_axis.axis);
    const std::string& name =
        g.axes[sa].values[g.scene_axis.member][pos[sa]].get_ref<const std::string&>();
    which = static_cast<std::size_t>(std::find(g.scenes.begin(), g.scenes.end(), name) -
                                     g.scenes.begin());
  }
  return pos;
}

/// The checks that interact between axes: integrator and time settings, history size, the
/// scene's own checks, a wear evolution's needs.
void check_case(const Draft& d, const std::vector<SignalId>& signals) {
  validate(d.integrator);
  validate(d.time);
  check_history_size(d.time, signals);
  const auto scene = build_checked(d.scene, d.parameters);
  if (d.wear_evolution.enabled && !scene->features().has(Feature::wear))
    throw InputError("parameters.wear.model",
                     "a wear_evolution study needs a scene with a wear model and "
                     "wear.model \"archard\"");
  if (d.wear_evolution.enabled && d.wear_evolution.clearance_limit == 0.0 &&
      d.wear_evolution.backlash_limit == 0.0 && d.wear_evolution.max_cycles >= 1e8)
    throw InputError("wear_evolution",
                     "needs a clearance_limit, a backlash_limit or a max_cycles below "
                     "1e8 to stop at");
}

/// Case `index` of the grid; `check`: the per-case validation and the id from the canonical
/// form (else the id stored by the validation pass).
CaseSpec resolve_case(const Grid& g, std::size_t index, bool check) {
  CaseSpec c;
  std::size_t which = 0;
  const std::vector<std::size_t> pos = grid_position(g, index, which);
  Draft d = g.bases[which];
  try {
    for (std::size_t a = 0; a < g.axes.size(); ++a)
      for (std::size_t k = 0; k < g.axes[a].keys.size(); ++k) {
        const std::string& key = g.axes[a].keys[k];
        const Json& v = g.axes[a].values[k][pos[a]];
        c.coordinates[key] = v;
        if (key == "scene") continue;  // chosen above
        if (key == "design.sample")
          c.design_sample = v.get<long>();
        else
          apply(d, key, v, g.origins.of_axis(g.axes[a].wheres[k]));
      }
    if (g.profiles_possible) attach_profiles(d.parameters, *g.profiles);
    if (g.profiles_possible && check) check_profiles_cover(d.parameters, d.time.end);
    if (check) check_case(d, g.scene_signals[which]);
  } catch (const InputError& e) {
    if (g.axes.empty()) throw;
    throw InputError(e.key_path(), e.problem() + " (grid case " + std::to_string(index) + ": " +
                                       c.coordinates.dump() + ")");
  }
  c.index = static_cast<long>(index);
  c.scene = d.scene;
  c.parameters = std::move(d.parameters);
  c.integrator = d.integrator;
  c.time = d.time;
  c.health = d.health;
  c.metrics = d.metrics;
  c.wear_evolution = d.wear_evolution;
  c.signals = g.scene_signals[which];
  c.output = g.output;
  if (check) {
    c.id = case_id(c);
  } else {
    char buf[17];
    std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(g.ids[index]));
    c.id = buf;
  }
  return c;
}

/// Every case resolved and checked once (its id kept), distinct points checked to be distinct
/// cases; afterwards a case is resolved again when it is asked for (study.cases[i]).
/// Every case resolved and checked once, its id kept: over the cores for a large study (the
/// cases are independent; each costs about 0.16 ms, mostly its scene's own checks and its id).
/// The error of the lowest failing case is the one reported, as a pass in order would.
void validate_cases(Grid& grid, std::size_t total) {
  constexpr std::size_t kParallelFrom = 4096;  // below, a thread team costs more than it saves
  grid.ids.assign(total, 0);
  std::size_t first_bad = total;
  std::exception_ptr error;
  std::mutex mutex;
  const auto n = static_cast<std::ptrdiff_t>(total);
#pragma omp parallel for schedule(dynamic, 256) if (total >= kParallelFrom)
  for (std::ptrdiff_t i = 0; i < n; ++i) {
    const auto index = static_cast<std::size_t>(i);
    {
      const std::lock_guard lock(mutex);
      if (index > first_bad) continue;  // a lower case failed: its error is the one reported
    }
    try {
      grid.ids[index] = std::stoull(resolve_case(grid, index, true).id, nullptr, 16);
    } catch (...) {
      const std::lock_guard lock(mutex);
      if (index < first_bad) {
        first_bad = index;
        error = std::current_exception();
      }
    }
  }
  if (error) std::rethrow_exception(error);
}

CaseList index_cases(std::shared_ptr<Grid> grid, std::size_t total) {
  validate_cases(*grid, total);
  std::vector<std::uint64_t> ids = grid->ids;
  std::sort(ids.begin(), ids.end());
  if (std::adjacent_find(ids.begin(), ids.end()) != ids.end())
    throw InputError("grid", "two grid points resolve to the same case (a repeated value?)");
  const std::shared_ptr<const Grid> frozen = grid;
  return CaseList(total, std::make_shared<const CaseList::Resolver>([frozen](std::size_t i) {
                    if (i >= frozen->ids.size())
                      throw std::out_of_range("case index " + std::to_string(i));
                    return resolve_case(*frozen, i, false);
                  }));
}

}  // namespace

Study parse_study(const Json& doc, const fs::path& file, const fs::path& results_root,
                  const std::vector<std::string>& overrides) {
  try {
    check_document(doc);
    Study study;
    read_identity(study, doc, file, results_root);
    auto grid = std::make_shared<Grid>();
    grid->origins.file = file.string();
    for (const std::string& o : overrides)
      grid->origins.set.emplace_back(o.substr(0, o.find('=')), o);
    grid->profiles = std::make_shared<ProfileStore>(file.parent_path());
    grid->axes = read_axes(study, doc);
    grid->scene_axis = find_scene_axis(grid->axes);
    read_scenes(study, doc, grid->axes, grid->scene_axis);
    const bool several = grid->scene_axis.axis >= 0;
    if (several) check_scene_axis_keys(study, doc, grid->axes);
    if (study.design) check_design_keys(*study.design, study.scenes);
    if (study.design) study.design_units = design_units(*study.design, study.scenes);
    if (!doc.contains("time"))
      throw InputError("time", "missing: {\"end\": ..., \"sample_interval\": ...}");
    build_bases(*grid, study, doc, several);
    const std::size_t total = count_cases(study, grid->axes);
    check_preset_axis(study, doc);
    grid->profiles_possible =
        profiles_possible_keys(study.axis_keys) ||
        std::any_of(grid->bases.begin(), grid->bases.end(),
                    [](const Draft& d) { return !profiles_in_use(d.parameters).empty(); });
    grid->scenes = study.scenes;
    grid->output = study.output;
    const std::shared_ptr<ProfileStore> profiles = grid->profiles;
    study.cases = index_cases(std::move(grid), total);
    study.profiles = profiles->records();
    return study;
  } catch (const InputError& e) {
    throw e.located(file.string());
  }
}

namespace {

/// Largest study file read (a study is a few kilobytes; a grid of 1e5 explicit values is about
/// 2 MB): anything larger is refused before it is read.
constexpr std::uintmax_t kMaxStudyBytes = 16u << 20;

/// Reads a study file: a regular file of at most kMaxStudyBytes, with no NUL byte.
std::string read_study_text(const fs::path& file) {
  const std::string name = file.string();
  std::error_code ec;
  const fs::file_status st = fs::status(file, ec);
  if (ec && ec != std::errc::no_such_file_or_directory)  // a loop of links, no permission, ...
    throw InputError("", "cannot open the study file: " + ec.message(), name);
  if (ec || !fs::exists(st)) throw InputError("", "cannot open the study file: no such file", name);
  if (fs::is_directory(st))
    throw InputError("", "is a directory; expected a study file (JSON)", name);
  if (!fs::is_regular_file(st))
    throw InputError("",
                     "is not a regular file (a device, FIFO or socket); expected a study "
                     "file (JSON)",
                     name);
  const std::uintmax_t size = fs::file_size(file, ec);
  auto too_large = [&] {
    return InputError("",
                      "is larger than 16 MiB, the limit of a study file; expected a study of "
                      "a few kilobytes (a grid is written as linspace/logspace axes)",
                      name);
  };
  if (!ec && size > kMaxStudyBytes) throw too_large();
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError("", "cannot open the study file", name);
  // in pieces of the size the file had (not into one zero-filled buffer of the limit: that
  // touched 16 MiB of memory in every run, most of a small sweep's peak RSS)
  const std::size_t piece = std::clamp<std::size_t>(ec ? 0 : size + 1, 4096, kMaxStudyBytes + 1);
  std::string text;
  while (in && text.size() <= kMaxStudyBytes) {
    const std::size_t have = text.size();
    text.resize(have + std::min(piece, kMaxStudyBytes + 1 - have));
    in.read(text.data() + have, static_cast<std::streamsize>(text.size() - have));
    text.resize(have + static_cast<std::size_t>(in.gcount()));
  }
  if (text.size() > kMaxStudyBytes) throw too_large();  // it grew while being read
  return text;
}

/// Key path of the value being parsed, from the parser's nesting (for duplicate-key messages).
struct KeyTracker {
  struct Level {
    bool array = false;
    std::size_t index = 0;          // next element of an array
    std::vector<std::string> keys;  // keys seen in an object
  };
  std::vector<Level> stack;
  std::string duplicate;  // key path of the first duplicate key, empty if none

  std::string path(const std::string& last) const {
    std::string p;
    for (std::size_t i = 0; i + 1 < stack.size(); ++i) {
      const Level& l = stack[i];
      if (l.array)
        p += "[" + std::to_string(l.index) + "]";
      else
        p += (p.empty() ? "" : ".") + l.keys.back();
    }
    return p.empty() ? last : p + "." + last;
  }
  void element_done() {
    if (!stack.empty() && stack.back().array) ++stack.back().index;
  }
};

/// Removes the value at dotted `path` from `obj`, written nested ({"contact": {"clearance":
/// ...}}), dotted ("contact.clearance") or mixed; empty objects left behind go too.
void erase_path(Json& obj, const std::string& path) {
  if (!obj.is_object()) return;
  std::vector<std::string> gone;
  for (auto it = obj.begin(); it != obj.end(); ++it) {
    const std::string& k = it.key();
    if (k == path) {
      gone.push_back(k);
    } else if (path.size() > k.size() && path.compare(0, k.size(), k) == 0 &&
               path[k.size()] == '.' && it->is_object()) {
      erase_path(*it, path.substr(k.size() + 1));
      if (it->empty()) gone.push_back(k);
    }
  }
  for (const std::string& k : gone) obj.erase(k);
}

/// Levenshtein distance (for "did you mean" in --set errors).
std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diag = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diag + (a[i - 1] != b[j - 1] ? 1 : 0)});
      diag = up;
    }
  }
  return row[b.size()];
}

/// A key path `--set` does not know: names the nearest one that exists, with its type and unit.
[[noreturn]] void unknown_override_key(const std::string& key, const std::string& section,
                                       const std::string& rest, const ParameterSet& params,
                                       const std::string& scene) {
  std::string best, type, unit;
  std::size_t best_d = std::string::npos;
  auto consider = [&](const std::string& name, const std::string& t, const std::string& u) {
    const std::size_t dist = edit_distance(rest, name);
    if (dist < best_d) best_d = dist, best = name, type = t, unit = u;
  };
  if (section == "parameters") {
    const Json leaves = params.leaves();  // outlives items()
    for (const auto& [p, leaf] : leaves.items())
      consider(p, json_type_name(leaf["value"]), leaf.value("unit", ""));
  } else {
    for (const StudyField& f : study_fields())
      if (f.section == section)
        consider(f.name, f.type == "integer" ? "an integer" : "a " + f.type, f.unit);
  }
  std::string m = section == "parameters" ? "unknown parameter of scene " + scene +
                                                " (see `rodend params " + scene + "`)"
                                          : "unknown " + section + " setting (see `rodend schema`)";
  if (!best.empty())
    m += "; nearest: " + section + "." + best + ", expected " + type +
         (unit.empty() || unit == "1" ? "" : " [" + unit + "]");
  throw InputError(key, m);
}

}  // namespace

/// `--set design.KEY=value` for the design's scalar keys; the loader checks the value.
void set_design_key(Json& doc, const std::string& rest, const Json& value) {
  std::vector<std::string> scalars;  // the design's keys but its factors
  for (const std::string_view k : design_keys())
    if (k != "factors") scalars.push_back("design." + std::string(k));
  if (std::find(scalars.begin(), scalars.end(), "design." + rest) == scalars.end())
    throw InputError("design." + rest, "expected one of " + alternatives(scalars, false) +
                                           " (the factors: --set design=...)");
  if (!doc.contains("design") || !doc["design"].is_object())
    throw InputError("design", "the study has no design block to change");
  doc["design"][rest] = value;
}

namespace {

/// The value of one --set key=value (`o`): its JSON, else the text as a string.
Json override_value(const std::string& o, const std::string& key, const std::string& text,
                    const fs::path& file) {
  Json value;
  try {
    (void)Json(o).dump();  // throws on bytes that are not UTF-8
  } catch (const Json::type_error&) {
    throw InputError(key, "expected UTF-8 text; the --set value has bytes that are not",
                     file.string());
  }
  try {
    value = Json::parse(text);
  } catch (const Json::out_of_range&) {  // 1e309: a number beyond a double's range
    throw InputError(key,
                     "the number " + text +
                         " is beyond a double's range; expected a finite "
                         "number (from --set " +
                         o + ")",
                     file.string());
  } catch (const Json::exception&) {
    value = text;  // not JSON: a string (--set scene=gravity-drop)
  }
  // before any copy of it (nlohmann copies recursively: 100,000 levels overflow the stack)
  if (nesting_depth(value) > kMaxDepth)
    throw InputError(key,
                     "the value is nested deeper than " + std::to_string(kMaxDepth) +
                         " levels (from --set); expected a value a study can hold",
                     file.string());
  return value;
}

/// A dotted --set key of a case section (parameters or settings.def), checked as the loader
/// will check it, on the study's scene.
void check_section_override(const Json& doc, const std::string& key, const std::string& section,
                            const std::string& rest, const Json& value) {
  const auto& dotted = case_sections();
  if (std::find(dotted.begin(), dotted.end(), section) == dotted.end())
    throw InputError(key, "'" + section + "' takes a whole value: --set " + section + "=...");
  if (!doc.contains("scene") || !doc["scene"].is_string())
    throw InputError("scene", "missing: which scene to run");
  Draft d;
  d.scene = doc["scene"].get<std::string>();
  d.parameters = ParameterSet::defaults_for(d.scene);
  const bool known =
      section == "parameters" ? d.parameters.has(rest) : find_setting(section, rest) != nullptr;
  if (!known) unknown_override_key(key, section, rest, d.parameters, d.scene);
  apply(d, key, value);
  if (doc.contains(section) && !doc[section].is_object())
    throw InputError(section, "expected an object, got " + json_type_name(doc[section]));
}

/// Sets one --set key to `value` in the study document.
void apply_override(Json& doc, const std::string& key, const Json& value) {
  if (!doc.is_object()) throw InputError("", "a study must be a JSON object");
  const auto dot = key.find('.');
  const std::string section = key.substr(0, dot);
  const auto& keys = study_keys();
  if (std::find(keys.begin(), keys.end(), section) == keys.end()) {
    std::string list;
    for (const auto& k : keys) list += (list.empty() ? "" : ", ") + k;
    throw InputError(key, "unknown key; expected one of " + list + " (with a dotted path for " +
                              alternatives(case_sections(), false, " and ") + ")");
  }
  if (dot == std::string::npos) {  // a whole top-level value (parse_study checks it)
    doc[key] = value;
    return;
  }
  const std::string rest = key.substr(dot + 1);
  if (section == "design")  // its scalar keys (seed, size, method, base, levels)
    return set_design_key(doc, rest, value);
  check_section_override(doc, key, section, rest, value);
  erase_path(doc[section], rest);
  // a preset sets every integrator field: asked for on the command line, it replaces the
  // study's integrator settings (an integrator key --set after it still applies on top)
  if (key == "integrator.preset") doc[section] = Json::object();
  doc[section][rest] = value;
}

}  // namespace

Json apply_overrides(Json doc, const std::vector<std::string>& overrides, const fs::path& file) {
  for (const std::string& o : overrides) {
    const auto eq = o.find('=');
    if (eq == std::string::npos || eq == 0)
      throw InputError("--set", "expected key.path=value, got '" + o + "'", file.string());
    const std::string key = o.substr(0, eq), text = o.substr(eq + 1);
    const Json value = override_value(o, key, text, file);
    try {
      apply_override(doc, key, value);
    } catch (const InputError& e) {
      throw InputError(e.key_path(), e.problem() + " (from --set " + o + ")", file.string());
    }
  }
  return doc;
}

Study load_study(const fs::path& file, const fs::path& results_root,
                 const std::vector<std::string>& overrides) {
  return parse_study_text(read_study_text(file), file, results_root, overrides);
}

namespace {

/// Parses JSON text, refusing a key that appears twice in one object: nlohmann keeps the last
/// one, which would silently drop a value the user wrote.
Json parse_unique_keys(const std::string& text, const fs::path& file) {
  KeyTracker keys;
  auto callback = [&keys](int, Json::parse_event_t event, Json& parsed) {
    using E = Json::parse_event_t;
    switch (event) {
      case E::object_start:
      case E::array_start:
        keys.stack.push_back({event == E::array_start, 0, {}});
        break;
      case E::object_end:
      case E::array_end:
        keys.stack.pop_back();
        keys.element_done();
        break;
      case E::key: {
        auto& seen = keys.stack.back().keys;
        const std::string k = parsed.get<std::string>();
        if (keys.duplicate.empty() && std::find(seen.begin(), seen.end(), k) != seen.end())
          keys.duplicate = keys.path(k);
        seen.push_back(k);
        break;
      }
      case E::value:
        keys.element_done();
        break;
    }
    return true;
  };
  Json doc = Json::parse(text, callback);
  if (!keys.duplicate.empty())
    throw InputError(keys.duplicate,
                     "the same key appears twice in one object; expected each key once (the "
                     "later value would silently replace the earlier)",
                     file.string());
  return doc;
}

/// The study's JSON document; a NUL byte, a syntax error or a number out of range is an
/// InputError naming the file and the line and column.
Json parse_study_json(const std::string& text, const fs::path& file) {
  if (text.find('\0') != std::string::npos) {
    const auto [line, col] = line_column(text, text.find('\0'));
    throw InputError("",
                     "a NUL byte at line " + std::to_string(line) + ", column " +
                         std::to_string(col) + "; expected JSON text (UTF-8) with no NUL byte",
                     file.string());
  }
  try {
    return parse_unique_keys(text, file);
  } catch (const Json::out_of_range& e) {
    // a number JSON can write but a double cannot hold (1e400)
    std::string what = e.what();
    const auto colon = what.find("] ");
    throw InputError(
        "",
        "number out of range: " + (colon == std::string::npos ? what : what.substr(colon + 2)) +
            " (expected a finite number)",
        file.string());
  } catch (const Json::parse_error& e) {
    const auto [line, col] = line_column(text, e.byte > 0 ? e.byte - 1 : 0);
    std::string what = e.what();
    // nlohmann's message starts with "[json.exception.parse_error.101] parse error at ..."
    const auto colon = what.find(": ");
    const std::string detail = colon == std::string::npos ? what : what.substr(colon + 2);
    throw InputError("",
                     "JSON syntax error at line " + std::to_string(line) + ", column " +
                         std::to_string(col) + ": " + detail,
                     file.string());
  }
}

}  // namespace

Study parse_study_text(const std::string& text, const fs::path& file, const fs::path& results_root,
                       const std::vector<std::string>& overrides) {
  Json doc = parse_study_json(text, file);
  if (overrides.empty()) return parse_study(doc, file, results_root);
  Study study =
      parse_study(apply_overrides(std::move(doc), overrides, file), file, results_root, overrides);
  study.overrides = overrides;
  return study;
}

}  // namespace rodend
