#include "core/params.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <string_view>

#include "core/json_text.hpp"
#include "core/profile_data.hpp"

namespace rodend {
namespace {

bool is_leaf(const Json& j) {
  return j.is_object() && j.contains("value");
}

void walk(const Json& node, const std::string& prefix,
          const std::function<void(const std::string&, const Json&)>& f) {
  for (auto it = node.begin(); it != node.end(); ++it) {
    const std::string path = prefix.empty() ? it.key() : prefix + "." + it.key();
    if (is_leaf(*it))
      f(path, *it);
    else if (it->is_object())
      walk(*it, path, f);
  }
}

/// The leaf at a dotted path, or null. Looked up by views of the path (nothing allocated):
/// scenes read their parameters by path while a study checks each of its cases.
template <class J>
J* find(J& tree, const std::string& path) {
  J* node = &tree;
  std::string_view rest(path);
  while (true) {
    const std::size_t dot = rest.find('.');
    if (!node->is_object() || is_leaf(*node)) return nullptr;
    const auto it = node->find(rest.substr(0, dot));
    if (it == node->end()) return nullptr;
    node = &*it;
    if (dot == std::string_view::npos) break;
    rest.remove_prefix(dot + 1);
  }
  return is_leaf(*node) ? node : nullptr;
}

}  // namespace

std::string json_type_name(const Json& j) {
  if (j.is_array()) {
    const bool numbers =
        std::all_of(j.begin(), j.end(), [](const Json& v) { return v.is_number(); });
    return "an array of " + std::to_string(j.size()) +
           (numbers ? (j.size() == 1 ? " number" : " numbers") : " values, not all numbers");
  }
  if (j.is_boolean()) return "a boolean";
  if (j.is_number()) return "a number";
  if (j.is_string()) return "a string";
  if (j.is_object()) return "an object";
  return "null";
}

ParameterSet ParameterSet::from_json(const Json& tree, const std::string& origin) {
  if (!tree.is_object()) throw InputError("", "a parameter tree must be a JSON object", origin);
  walk(tree, "", [&](const std::string& path, const Json& leaf) {
    const Json& v = leaf["value"];
    const bool vec = v.is_array() && !v.empty() &&
                     std::all_of(v.begin(), v.end(), [](const Json& e) { return e.is_number(); });
    if (!(v.is_number() || v.is_string() || v.is_boolean() || vec))
      throw InputError(path + ".value", "expected a number, string, boolean or array of numbers",
                       origin);
    if (!leaf.contains("unit") || !leaf["unit"].is_string())
      throw InputError(path + ".unit", "every parameter needs a unit string (\"1\" if none)",
                       origin);
    const std::string src = leaf.value("source", "");
    const auto source = choice_from_name<ParameterSource>(src);
    if (!source) throw InputError(path + ".source", choice_expected<ParameterSource>(src), origin);
    if (*source != ParameterSource::thesis && leaf.value("note", "").empty())
      throw InputError(path + ".note", "an assumed or derived value needs a note saying why",
                       origin);
  });
  ParameterSet p;
  p.tree_ = tree;
  return p;
}

bool ParameterSet::has(const std::string& path) const {
  return find(tree_, path) != nullptr;
}

const Json& ParameterSet::leaf(const std::string& path) const {
  const Json* l = find(tree_, path);
  if (!l) throw InputError(path, "unknown parameter");
  return *l;
}

void ParameterSet::set(const std::string& path, const Json& value, const std::string& source,
                       const std::string& note) {
  Json* l = find(tree_, path);
  if (!l) throw InputError(path, "unknown parameter (see `rodend params SCENE`)");
  const Json& old = (*l)["value"];
  const bool same_array =
      old.is_array() && value.is_array() && old.size() == value.size() &&
      std::all_of(value.begin(), value.end(), [](const Json& v) { return v.is_number(); });
  const bool ok = (old.is_number() && value.is_number()) ||
                  (old.is_string() && value.is_string()) ||
                  (old.is_boolean() && value.is_boolean()) || same_array;
  if (!ok)
    throw InputError(path, "expected " + json_type_name(old) + ", got " + json_type_name(value));
  if (old.is_string() && l->contains("choices")) {
    const Json& choices = (*l)["choices"];
    if (std::find(choices.begin(), choices.end(), value) == choices.end()) {
      // value is a string here (old is one); the choices are the menu's names
      const auto names = choices.get<std::vector<std::string>>();
      const std::vector<std::string_view> views(names.begin(), names.end());
      const std::string_view near = nearest_name(views, value.get<std::string>());
      throw InputError(path,
                       "expected one of " + choices.dump() + ", got " + value.dump() +
                           (near.empty() ? "" : " (did you mean \"" + std::string(near) + "\"?)"));
    }
  }
  if (value.is_number() && !std::isfinite(value.get<double>()))
    throw InputError(path, "expected a finite number");
  if (!source.empty()) {
    if (!l->contains("default"))  // the scene's default, kept through later overrides
      (*l)["default"] = {
          {"value", old}, {"source", l->value("source", "")}, {"note", l->value("note", "")}};
    (*l)["source"] = source;
    (*l)["note"] = note;
  }
  (*l)["value"] = value;
  attached_.erase(path);
}

void ParameterSet::attach(const std::string& path, std::shared_ptr<const ProfileData> data) {
  leaf(path);  // an unknown key throws
  attached_[path] = std::move(data);
}

std::shared_ptr<const ProfileData> ParameterSet::attached(const std::string& path) const {
  const auto it = attached_.find(path);
  return it == attached_.end() ? nullptr : it->second;
}

double ParameterSet::number(const std::string& path) const {
  const Json& v = leaf(path)["value"];
  if (!v.is_number()) throw InputError(path, "expected a number");
  return v.get<double>();
}
std::string ParameterSet::text(const std::string& path) const {
  const Json& v = leaf(path)["value"];
  if (!v.is_string()) throw InputError(path, "expected a string");
  return v.get<std::string>();
}
bool ParameterSet::flag(const std::string& path) const {
  const Json& v = leaf(path)["value"];
  if (!v.is_boolean()) throw InputError(path, "expected a boolean");
  return v.get<bool>();
}
Vec3 ParameterSet::vec3(const std::string& path) const {
  const Json& v = leaf(path)["value"];
  if (!v.is_array() || v.size() != 3 ||
      !std::all_of(v.begin(), v.end(), [](const Json& e) { return e.is_number(); }))
    throw InputError(path, "expected an array of 3 numbers");
  return Vec3(v[0].get<double>(), v[1].get<double>(), v[2].get<double>());
}
std::string ParameterSet::unit(const std::string& path) const {
  return leaf(path).value("unit", "");
}

Json ParameterSet::values() const {
  Json out = Json::object();  // nlohmann::json objects keep keys sorted
  walk(tree_, "", [&](const std::string& path, const Json& l) { out[path] = l["value"]; });
  return out;
}
Json ParameterSet::leaves() const {
  Json out = Json::object();
  walk(tree_, "", [&](const std::string& path, const Json& l) { out[path] = l; });
  for (const auto& [path, data] : attached_) {
    out[path]["resolved_path"] = data->resolved;
    out[path]["content_fnv1a64"] = data->content_hash;
  }
  return out;
}
std::vector<std::string> ParameterSet::paths() const {
  std::vector<std::string> out;
  walk(tree_, "", [&](const std::string& path, const Json&) { out.push_back(path); });
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace rodend
