// The --set overrides: each key=value read (its JSON, else a string), checked as the loader
// will check it, and written into the study document at its key path.
#include <algorithm>

#include "core/edit_distance.hpp"
#include "core/json_text.hpp"
#include "sweep/study/loader.hpp"

namespace rodend {
namespace fs = std::filesystem;
using namespace study_detail;

namespace {

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

}  // namespace

std::string study_detail::nearest_key(const std::string& section, const std::string& rest,
                                      const std::vector<const ParameterSet*>& params) {
  std::string best, type, unit;
  std::size_t best_d = std::string::npos;
  auto consider = [&](const std::string& name, const std::string& t, const std::string& u) {
    const std::size_t dist = edit_distance(rest, name);
    if (dist < best_d) best_d = dist, best = name, type = t, unit = u;
  };
  if (section == "parameters") {
    for (const ParameterSet* p : params) {
      const Json leaves = p->leaves();  // outlives items()
      for (const auto& [path, leaf] : leaves.items())
        consider(path, json_type_name(leaf["value"]), leaf.value("unit", ""));
    }
  } else {
    for (const StudyField& f : study_fields())
      if (f.section == section)
        consider(f.name, f.type == "integer" ? "an integer" : "a " + f.type, f.unit);
  }
  if (best.empty()) return "";
  return "; nearest: " + section + "." + best + ", expected " + type +
         (unit.empty() || unit == "1" ? "" : " [" + unit + "]");
}

void study_detail::unknown_key(const std::string& key, const std::string& section,
                               const std::string& rest, const ParameterSet& params,
                               const std::string& scene) {
  const std::string m =
      section == "parameters"
          ? "unknown parameter of scene " + scene + " (see `rodend params " + scene + "`)"
          : "unknown " + section + " setting (see `rodend schema`)";
  throw InputError(key, m + nearest_key(section, rest, {&params}));
}

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
  if (!known) unknown_key(key, section, rest, d.parameters, d.scene);
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
  if (section == "sensors") {  // a value checked here; a sensor's signal once the case is built
    SensorSettings probe;
    apply_sensor_key(probe, rest, value, key);
    if (doc.contains(section) && !doc[section].is_object())
      throw InputError(section, "expected an object, got " + json_type_name(doc[section]));
    if (doc.contains(section)) erase_path(doc[section], rest);
    doc[section][rest] = value;
    return;
  }
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

}  // namespace rodend
