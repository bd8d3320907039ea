// Applying a study's values to the draft of a case: one value by its key path (apply), a
// section object (apply_section), and the study's "output" key (parse_output).
#include <algorithm>
#include <string>
#include <utility>
#include <vector>

#include "core/json_text.hpp"
#include "sweep/study/loader.hpp"

namespace rodend::study_detail {

namespace {

/// A path the study names for its results: not empty (NUL characters are refused before).
fs::path output_path(const Json& v, const std::string& key) {
  const std::string s = need_string(v, key);
  if (s.empty())
    throw InputError(key,
                     "expected a non-empty directory path (or no \"output\" key: "
                     "results/<name>)");
  return fs::path(s);
}

}  // namespace

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

void apply(Draft& d, const std::string& key, const Json& v,
           const std::pair<std::string, std::string>& from) {
  const auto dot = key.find('.');
  const std::string section = key.substr(0, dot);
  const std::string field = dot == std::string::npos ? "" : key.substr(dot + 1);
  if (field.empty())
    throw InputError(key, "expected a key path such as parameters.contact.clearance");
  if (section == "parameters") {
    if (d.skip_absent_parameters && !d.parameters.has(field)) return;
    if (!d.parameters.has(field)) unknown_key(key, section, field, d.parameters, d.scene);
    try {
      d.parameters.set(field, v, from.first, from.second);
    } catch (const InputError& e) {
      throw e.located("", "parameters");
    }
    return;
  }
  if (section == "sensors") return apply_sensor_key(d.sensors, field, v, key);
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
  // a preset sets every integrator field, a default sensor set every key of its sensors: apply
  // them first, so the keys beside them override them
  std::stable_partition(flat.begin(), flat.end(), [](const auto& kv) {
    return kv.first == "integrator.preset" || kv.first == "sensors.defaults";
  });
  for (const auto& [k, v] : flat) apply(d, k, v, origins.of_study(k));
}

}  // namespace rodend::study_detail
