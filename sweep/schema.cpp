#include "sweep/schema.hpp"

#include <iomanip>
#include <map>
#include <set>
#include <sstream>

#include "core/scene.hpp"
#include "core/signals.hpp"
#include "sweep/study.hpp"

namespace rodend {
namespace {

/// " [unit]" for a unit worth printing.
std::string unit_note(const std::string& unit) {
  return unit.empty() || unit == "1" ? "" : " [" + unit + "]";
}

/// The schema of one parameter value, from the type of its default (what ParameterSet::set
/// accepts: the same JSON type, a numeric array of the same length, one of the choices).
Json parameter_schema(const Json& leaf) {
  const Json& v = leaf["value"];
  Json s;
  if (v.is_number())
    s = {{"type", "number"}};
  else if (v.is_boolean())
    s = {{"type", "boolean"}};
  else if (v.is_string()) {
    s = {{"type", "string"}};
    if (leaf.contains("choices")) s["enum"] = leaf["choices"];
  } else if (v.is_array())
    s = {{"type", "array"},
         {"items", {{"type", "number"}}},
         {"minItems", v.size()},
         {"maxItems", v.size()}};
  std::string d = leaf.contains("note") ? leaf["note"].get<std::string>() : std::string();
  s["description"] = d + unit_note(leaf.value("unit", ""));
  s["default"] = v;
  return s;
}

/// The "sensors" block (sweep/sensors.hpp): a default set, the seed, the noise factor and the
/// sensors by name.
Json sensors_schema() {
  Json signals = Json::array();
  for (SignalId id : kStepSignals)
    if (id != SignalId::time) signals.push_back(std::string(signal_spec(id).name));
  // one property per key of sweep/sensor_settings.def, its type and bounds from its check
  const auto property = [&](SensorCheck check, const std::string& unit, const char* text) {
    Json p = {{"type", "number"}};
    if (check == SensorCheck::signal) p = Json{{"enum", signals}};
    if (check == SensorCheck::zero_to_two)
      p = {{"type", "integer"}, {"minimum", 0}, {"maximum", 2}};
    if (check == SensorCheck::at_least_zero) p["minimum"] = 0;
    if (check == SensorCheck::above_zero) p["exclusiveMinimum"] = 0;
    p["description"] = text + (unit == "signal" ? " [unit of the signal]" : unit_note(unit));
    return p;
  };
  Json properties = Json::object();
#define RODEND_SENSOR_SETTING(key, type, check, unit, value, provenance, what, description) \
  properties[#key] = property(SensorCheck::check, unit, description);
#include "sweep/sensor_settings.def"
#undef RODEND_SENSOR_SETTING
  const Json sensor = {
      {"type", "object"}, {"additionalProperties", false}, {"properties", properties}};
  return {{"type", "object"},
          {"description",
           "instruments recording signals with noise, bias, quantisation, a "
           "low-pass and their own sampling rate (docs/sensors.md)"},
          {"properties",
           {{"defaults", {{"enum", sensor_set_names()}}},
            {"seed", {{"type", "integer"}, {"minimum", 0}}},
            {"noise_scale", {{"type", "number"}, {"minimum", 0}}}}},
          {"additionalProperties", sensor}};
}

/// design.correlation: its kind (the catalogue of correlation kinds) and its matrix.
Json correlation_schema() {
  Json kinds_of_correlation = Json::array();
  for (const auto& [k, name] : correlation_kinds())
    kinds_of_correlation.push_back(std::string(name));
  return {
      {"type", "object"},
      {"description",
       "the factors' correlation matrix, a normal copula (monte-carlo, "
       "latin-hypercube and sobol designs)"},
      {"required", {"kind", "matrix"}},
      {"additionalProperties", false},
      {"properties",
       {{"kind", {{"enum", kinds_of_correlation}}},
        {"matrix",
         {{"type", "array"}, {"items", {{"type", "array"}, {"items", {{"type", "number"}}}}}}}}}};
}

/// The "design" block (sweep/design.hpp), from its catalogues: the methods, and per
/// distribution its parameters.
Json design_schema(const std::string& key_pattern) {
  Json methods = Json::array(), bases = Json::array(), kinds = Json::array(),
       per_kind = Json::array(), drawn = Json::array(), given = Json::array();
  for (const auto& m : design_method_catalogue()) {
    methods.push_back(std::string(m.name));
    if (m.sample) bases.push_back(std::string(m.name));
    (m.distributions ? drawn : given).push_back(std::string(m.name));
  }
  for (const auto& d : distribution_catalogue()) {
    kinds.push_back(std::string(d.name));
    Json props = {{"key", true}, {"distribution", true}};
    Json required = {"key", "distribution"};
    for (const auto k : d.keys) {
      const bool list = k == "values" || k == "weights";
      props[std::string(k)] = list ? Json{{"type", "array"}, {"items", {{"type", "number"}}}}
                                   : Json{{"type", "number"}};
      if (k != "weights") required.push_back(std::string(k));
    }
    per_kind.push_back(
        {{"if", {{"properties", {{"distribution", {{"const", std::string(d.name)}}}}}}},
         {"then",
          {{"properties", props}, {"required", required}, {"additionalProperties", false}}}});
  }
  const Json correlation = correlation_schema();
  const Json factor = {
      {"type", "object"},
      {"required", {"key", "distribution"}},
      {"properties",
       {{"key", {{"type", "string"}, {"pattern", key_pattern}, {"description", "full key path"}}},
        {"distribution", {{"enum", kinds}}}}},
      {"allOf", per_kind}};
  return {
      {"type", "object"},
      {"description", "a sampled design: factors drawn from distributions (docs/uncertainty.md)"},
      {"required", {"method"}},
      {"allOf",
       {{{"if", {{"properties", {{"method", {{"enum", drawn}}}}}}},
         {"then", {{"required", {"size", "seed", "factors"}}}}},
        {{"if", {{"properties", {{"method", {{"enum", given}}}}}}},
         {"then", {{"required", {"file"}}}}}}},
      {"additionalProperties", false},
      {"properties",
       {{"method", {{"enum", methods}}},
        {"size", {{"type", "integer"}, {"minimum", 1}}},
        {"seed", {{"type", "integer"}, {"minimum", 0}}},
        {"levels",
         {{"type", "integer"}, {"minimum", 2}, {"maximum", kMaxMorrisLevels}, {"multipleOf", 2}}},
        {"base", {{"enum", bases}}},
        {"correlation", correlation},
        {"file",
         {{"type", "string"},
          {"description",
           "file design: a CSV file of points, a header of factor key paths, one row per "
           "case (relative to the study file's folder)"}}},
        {"factors",
         {{"type", "array"},
          {"minItems", 1},
          {"maxItems", kMaxDesignFactors},
          {"items", factor}}}}}};
}

/// A scene's parameters object: each parameter by its dotted path, or nested at any of its dots
/// ("contact.clearance": x, or "contact": {"clearance": x}); nothing else.
Json nested_parameters(const std::vector<std::pair<std::string, Json>>& leaves) {
  Json props = Json::object();
  std::map<std::string, std::vector<std::pair<std::string, Json>>> below;  // prefix -> the rest
  for (const auto& [path, schema] : leaves) {
    props[path] = schema;
    for (auto dot = path.find('.'); dot != std::string::npos; dot = path.find('.', dot + 1))
      below[path.substr(0, dot)].emplace_back(path.substr(dot + 1), schema);
  }
  for (const auto& [prefix, rest] : below) props[prefix] = nested_parameters(rest);
  return {{"type", "object"}, {"additionalProperties", false}, {"properties", props}};
}

/// What a study of these scenes may name: its parameters (nested or dotted), and the keys of its
/// grid axes and design factors (the scenes' parameters and every section setting).
Json scene_rule(const std::vector<std::string>& scenes, const Json& condition) {
  std::vector<std::pair<std::string, Json>> leaves;
  std::set<std::string> seen;
  Json keys = Json::array();
  for (const StudyField& f : study_fields())
    if (f.section != "output") keys.push_back(f.section + "." + f.name);
  for (const std::string& scene : scenes) {
    const Json all = ParameterSet::defaults_for(scene).leaves();
    for (const auto& [path, leaf] : all.items())
      if (seen.insert(path).second) {
        leaves.emplace_back(path, parameter_schema(leaf));
        keys.push_back("parameters." + path);
      }
  }
  const Json factor_key = {{"properties", {{"key", {{"enum", keys}}}}}};
  Json axis_keys = keys;
  axis_keys.push_back("scene");
  // a sensors key names a sensor of the study's own choosing (docs/sensors.md)
  const Json key_rule = {{"anyOf", {{{"enum", axis_keys}}, {{"pattern", "^sensors\\."}}}}};
  const Json axis_key = {{"properties", {{"key", key_rule}}}};
  const Json grid_entry = {
      {"anyOf",
       {{{"required", {"key"}}, {"properties", {{"key", key_rule}}}},
        {{"required", {"zip"}}, {"properties", {{"zip", {{"items", axis_key}}}}}}}}};
  return {{"if", condition},
          {"then",
           {{"properties",
             {{"parameters", nested_parameters(leaves)},
              {"grid", {{"items", grid_entry}}},
              {"design", {{"properties", {{"factors", {{"items", factor_key}}}}}}}}}}}};
}

/// Per scene, what a study of it may name; a study whose scene is a grid axis may name what any
/// scene has (the loader then checks that some scene of the axis has it).
Json scene_rules() {
  Json rules = Json::array();
  std::vector<std::string> every;
  for (const auto& s : scene_catalogue()) {
    every.emplace_back(s.name);
    rules.push_back(scene_rule(
        {std::string(s.name)},
        {{"properties", {{"scene", {{"const", std::string(s.name)}}}}}, {"required", {"scene"}}}));
  }
  rules.push_back(scene_rule(every, {{"not", {{"required", {"scene"}}}}}));
  return rules;
}

/// The sections of settings, from the loader's field list (sweep/settings.def), as schema
/// properties; `sections` gets the sections a key path may start with (output is the study's,
/// not a grid key).
Json settings_properties(std::set<std::string>& sections) {
  Json props = Json::object();
  for (const StudyField& f : study_fields()) {
    if (f.section != "output") sections.insert(f.section);
    Json& sec = props[f.section];
    if (sec.is_null())
      sec = {{"type", "object"}, {"additionalProperties", false}, {"properties", Json::object()}};
    Json p = {{"type", f.type}, {"description", f.description + unit_note(f.unit)}};
    if (!f.choices.empty()) p["enum"] = f.choices;
    if (!f.default_value.is_null()) p["default"] = f.default_value;
    if (!f.minimum.is_null()) p[f.exclusive_minimum ? "exclusiveMinimum" : "minimum"] = f.minimum;
    if (!f.maximum.is_null()) p["maximum"] = f.maximum;
    sec["properties"][f.name] = p;
  }
  props["time"]["required"] = {"end", "sample_interval"};
  // validate(TimeSettings) (core/integrator.cpp) refuses a time <= 0, with the other time rules
  props["time"]["properties"]["end"]["exclusiveMinimum"] = 0;
  props["time"]["properties"]["sample_interval"]["exclusiveMinimum"] = 0;
  props["integrator"]["description"] =
      "integrator settings; a study without them uses the balanced preset";
  props["time"]["description"] = "end time and history sample interval";
  props["health"]["description"] = "limits beyond which a run stops as failed";
  props["metrics"]["description"] = "settings of the summary metrics";
  props["wear_evolution"]["description"] =
      "makes every case a wear evolution (needs parameters wear.model \"archard\")";
  return props;
}

/// The study's own top-level keys (name, scene, parameters, signals, grid, design, output),
/// added to the settings' properties.
void add_study_properties(Json& props, const std::string& key_pattern) {
  Json scenes = Json::array(), signals = Json::array();
  for (const auto& s : scene_catalogue()) scenes.push_back(std::string(s.name));
  for (const auto& s : signal_catalogue()) signals.push_back(std::string(s.name));
  props["name"] = {{"type", "string"},
                   {"pattern", "^[^/]+$"},
                   {"description",
                    "study name; results go to results/<name>/ (default: the "
                    "file's stem)"}};
  props["description"] = {{"type", "string"}, {"description", "what the study is for"}};
  props["scene"] = {{"enum", scenes}, {"description", "the scene (rodend scenes)"}};
  props["parameters"] = {
      {"type", "object"},
      {"description",
       "overrides of the scene's defaults, by dotted key path (\"contact.clearance\": 1e-4) or "
       "nested objects (rodend params SCENE)"}};
  props["signals"] = {
      {"description", "\"all\" (default) or a list of signal names (rodend signals)"},
      {"oneOf", {{{"const", "all"}}, {{"type", "array"}, {"items", {{"enum", signals}}}}}}};
  props["grid"] = {{"type", "array"},
                   {"description", "axes combined as a cartesian product, last axis fastest"},
                   {"items", {{"$ref", "#/$defs/grid_entry"}}}};
  props["design"] = design_schema(key_pattern);
  props["sensors"] = sensors_schema();
  props["output"] = {{"description",
                      "results directory (default results/<name>), or an object with it and the "
                      "storage settings of the histories"},
                     {"oneOf", {{{"type", "string"}}, props["output"]}}};
  // the top-level keys are the loader's list: fail loudly if the two ever disagree
  for (const std::string& k : study_keys())
    if (!props.contains(k)) throw std::logic_error("study_schema: no schema for key " + k);
}

/// The grid's entries: an axis (values, linspace or logspace of a key path) or a zip of axes.
Json grid_defs(const std::string& key_pattern) {
  const Json number3 = {
      {"type", "array"},
      {"prefixItems",
       {{{"type", "number"}}, {{"type", "number"}}, {{"type", "integer"}, {"minimum", 1}}}},
      {"minItems", 3},
      {"maxItems", 3}};
  const Json axis = {
      {"type", "object"},
      {"required", {"key"}},
      {"additionalProperties", false},
      {"properties",
       {{"key", {{"type", "string"}, {"pattern", key_pattern}, {"description", "full key path"}}},
        {"values", {{"type", "array"}, {"minItems", 1}}},
        {"linspace", number3},
        {"logspace", number3}}},
      {"oneOf",
       {{{"required", {"values"}}}, {{"required", {"linspace"}}}, {{"required", {"logspace"}}}}}};
  const Json zip = {
      {"type", "object"},
      {"required", {"zip"}},
      {"additionalProperties", false},
      {"properties",
       {{"zip", {{"type", "array"}, {"minItems", 1}, {"items", {{"$ref", "#/$defs/axis"}}}}}}}};
  return {{"axis", axis}, {"grid_entry", {{"oneOf", {axis, zip}}}}};
}

}  // namespace

Json study_schema() {
  std::set<std::string> sections{"parameters", "sensors"};
  Json props = settings_properties(sections);
  std::string key_pattern;
  for (const std::string& s : sections) key_pattern += (key_pattern.empty() ? "" : "|") + s;
  // a full key path, or "scene": the scene as a grid axis (then no top-level "scene")
  key_pattern = "^((" + key_pattern + ")\\.|scene$)";
  add_study_properties(props, key_pattern);
  return {{"$schema", "https://json-schema.org/draft/2020-12/schema"},
          {"$id", "urn:rodend:study"},
          {"title", "rodend study"},
          {"description",
           "A rodend study file (README \"Studies\"), generated by `rodend schema` from the "
           "loader's own lists. The loader checks more than this (ranges, the scene's physical "
           "checks, grid sizes)."},
          {"type", "object"},
          {"required", {"time"}},
          // the scene, or a grid whose axis "scene" names the scenes
          {"anyOf", Json::array({{{"required", {"scene"}}}, {{"required", {"grid"}}}})},
          {"additionalProperties", false},
          {"properties", props},
          {"allOf", scene_rules()},
          {"$defs", grid_defs(key_pattern)}};
}

std::string study_settings_markdown() {
  auto cell = [](std::string text) {  // a table cell: '|' escaped
    for (std::size_t i = 0; (i = text.find('|', i)) != std::string::npos; i += 2)
      text.insert(i, "\\");
    return text;
  };
  auto text = [](const Json& v) {  // numbers as 1e+08, 10000, 0.05
    if (!v.is_number()) return v.dump();
    std::ostringstream o;
    o << std::setprecision(15) << v.get<double>();
    return o.str();
  };
  std::string out = "| setting | type | unit | default | description |\n|---|---|---|---|---|\n";
  for (const StudyField& f : study_fields()) {
    std::string type = f.type;
    if (!f.maximum.is_null())
      type += " " + text(f.minimum) + " to " + text(f.maximum);
    else if (!f.minimum.is_null())
      type += (f.exclusive_minimum ? " > " : " >= ") + text(f.minimum);
    for (std::size_t i = 0; i < f.choices.size(); ++i)
      type += (i == 0 ? ": `" : ", `") + f.choices[i] + "`";
    out += "| `" + f.section + "." + f.name + "` | " + type + " | " + f.unit + " | " +
           (f.default_value.is_null() ? "" : "`" + text(f.default_value) + "`") + " | " +
           cell(f.description) + " |\n";
  }
  return out;
}

}  // namespace rodend
