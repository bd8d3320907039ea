// Scene defaults composed from part files: see core/scene_parameters.hpp.
#include "core/scene_parameters.hpp"

#include <algorithm>
#include <functional>
#include <map>

#include "core/menus.hpp"

namespace rodend {
namespace {

using LeafFn = std::function<void(const std::string&, const Json&)>;

bool is_leaf(const Json& j) {
  return j.is_object() && j.contains("value");
}

std::string join(const std::string& prefix, const std::string& key) {
  return prefix.empty() ? key : prefix + "." + key;
}

std::string comma_list(const std::vector<std::string>& names) {
  std::string s;
  for (const std::string& n : names) s += (s.empty() ? "" : ", ") + n;
  return s;
}

/// Calls f(path, leaf) for every leaf under `node`; a member that is neither a leaf nor a group
/// of leaves is an error.
void for_each_leaf(const Json& node, const std::string& prefix, const std::string& file,
                   const LeafFn& f) {
  for (auto it = node.begin(); it != node.end(); ++it) {
    const std::string path = join(prefix, it.key());
    if (is_leaf(*it))
      f(path, *it);
    else if (it->is_object())
      for_each_leaf(*it, path, file, f);
    else
      throw InputError(
          path, "expected a leaf {\"value\", \"unit\", \"source\", \"note\"} or a group", file);
  }
}

/// The leaf at dotted `path` in `tree`, or null.
Json* find_leaf(Json& tree, const std::string& path) {
  Json* node = &tree;
  std::size_t start = 0;
  for (std::size_t dot = 0; dot != std::string::npos; start = dot + 1) {
    dot = path.find('.', start);
    const std::string key = path.substr(start, dot == std::string::npos ? dot : dot - start);
    if (!node->is_object() || is_leaf(*node) || !node->contains(key)) return nullptr;
    node = &(*node)[key];
  }
  return is_leaf(*node) ? node : nullptr;
}

/// Puts `leaf` at dotted `path` in `tree`, making the groups on the way; a path through a leaf
/// or onto a group is an error.
void place(Json& tree, const std::string& path, const Json& leaf, const std::string& file) {
  Json* node = &tree;
  std::size_t start = 0;
  for (std::size_t dot = path.find('.'); dot != std::string::npos; dot = path.find('.', start)) {
    node = &(*node)[path.substr(start, dot - start)];
    if (is_leaf(*node))
      throw InputError(path, "goes inside the leaf " + path.substr(0, dot) + " (a value)", file);
    start = dot + 1;
  }
  Json& slot = (*node)[path.substr(start)];
  if (!slot.is_null() && !is_leaf(slot))
    throw InputError(path, "a leaf here would replace a group of parameters", file);
  slot = leaf;
}

/// The parameters of part `name` (its file checked), from the table `parts`.
Json part_parameters(const std::string& name, std::span<const EmbeddedJson> parts,
                     const std::string& file, const std::string& where) {
  const auto it = std::find_if(parts.begin(), parts.end(),
                               [&](const EmbeddedJson& p) { return p.first == name; });
  if (it == parts.end()) {
    std::vector<std::string> known;
    for (const EmbeddedJson& p : parts) known.emplace_back(p.first);
    throw InputError(where, "unknown part '" + name + "'; expected one of: " + comma_list(known),
                     file);
  }
  const std::string part_file = name + ".part.json";
  const Json doc = Json::parse(it->second);
  if (doc.value("part", "") != name)
    throw InputError("part", "expected the part's own name, \"" + name + "\"", part_file);
  if (!doc.contains("parameters") || !doc["parameters"].is_object())
    throw InputError("parameters", "expected an object of parameters", part_file);
  (void)ParameterSet::from_json(doc["parameters"], part_file);  // every leaf complete
  return doc["parameters"];
}

/// Places the parts the scene file names, in order; `owner` records which part placed each leaf.
void place_parts(Json& tree, std::map<std::string, std::string>& owner, const Json& doc,
                 const std::string& file, std::span<const EmbeddedJson> parts) {
  if (!doc.contains("parts")) return;
  const Json& list = doc["parts"];
  if (!list.is_array()) throw InputError("parts", "expected an array of {\"part\", \"at\"}", file);
  for (std::size_t i = 0; i < list.size(); ++i) {
    const std::string where = "parts[" + std::to_string(i) + "]";
    const Json& e = list[i];
    if (!e.is_object() || !e.contains("part") || !e["part"].is_string())
      throw InputError(where + ".part", "expected the name of a part", file);
    for (auto it = e.begin(); it != e.end(); ++it)
      if (it.key() != "part" && it.key() != "at")
        throw InputError(where + "." + it.key(), "unknown key; expected \"part\" or \"at\"", file);
    if (e.contains("at") && !(e["at"].is_string() && !e["at"].get<std::string>().empty()))
      throw InputError(where + ".at", "expected a dotted key path (omit it for the root)", file);
    const std::string name = e["part"].get<std::string>();
    const Json params = part_parameters(name, parts, file, where + ".part");
    for_each_leaf(params, e.value("at", ""), file, [&](const std::string& path, const Json& leaf) {
      if (const auto o = owner.find(path); o != owner.end())
        throw InputError(
            path,
            "placed twice, by part '" + o->second + "' and by part '" + name + "' (" + where + ")",
            file);
      place(tree, path, leaf, file);
      owner[path] = name;
    });
  }
}

/// An override may replace a part leaf's value (of the same type), source, note and choices.
void check_override(const Json& base, const Json& over, const std::string& path,
                    const std::string& part, const std::string& file) {
  if (over.contains("unit") && over["unit"] != base["unit"])
    throw InputError(path + ".unit",
                     "part '" + part + "' gives this leaf the unit " + base["unit"].dump() +
                         "; an override may not change it",
                     file);
  const Json& a = base["value"];
  const Json& b = over["value"];
  const bool same = (a.is_number() && b.is_number()) || (a.is_string() && b.is_string()) ||
                    (a.is_boolean() && b.is_boolean()) ||
                    (a.is_array() && b.is_array() && a.size() == b.size());
  if (!same)
    throw InputError(path + ".value",
                     "part '" + part + "' gives " + a.dump() + "; an override must keep its type",
                     file);
}

/// Merges the scene's own parameters over the parts' leaves.
void merge_own(Json& tree, const std::map<std::string, std::string>& owner, const Json& own,
               const std::string& file) {
  for_each_leaf(own, "", file, [&](const std::string& path, const Json& leaf) {
    const auto o = owner.find(path);
    if (o == owner.end()) {
      if (!leaf.contains("unit"))
        throw InputError(path,
                         "overrides a key that no part defines: give the whole leaf (value, "
                         "unit, source, note) or correct the key path",
                         file);
      place(tree, path, leaf, file);
      return;
    }
    Json& base = *find_leaf(tree, path);
    check_override(base, leaf, path, o->second, file);
    for (auto it = leaf.begin(); it != leaf.end(); ++it) base[it.key()] = *it;
  });
}

/// Replaces each leaf's "catalogue" by the catalogue's names as its "choices".
void resolve_catalogues(Json& node, const std::string& prefix, const std::string& file) {
  for (auto it = node.begin(); it != node.end(); ++it) {
    const std::string path = join(prefix, it.key());
    if (!is_leaf(*it)) {
      if (it->is_object()) resolve_catalogues(*it, path, file);
      continue;
    }
    if (!it->contains("catalogue")) continue;
    const Json& c = (*it)["catalogue"];
    const std::vector<std::string> names =
        c.is_string() ? parameter_catalogue(c.get<std::string>()) : std::vector<std::string>{};
    if (names.empty())
      throw InputError(path + ".catalogue",
                       "expected one of: " + comma_list(parameter_catalogue_names()), file);
    if (it->contains("choices"))
      throw InputError(path + ".choices", "a leaf lists its choices or names a catalogue, not both",
                       file);
    (*it)["choices"] = names;
    it->erase("catalogue");
  }
}

}  // namespace

Json compose_scene_parameters(const Json& scene_doc, const std::string& file,
                              std::span<const EmbeddedJson> parts) {
  if (!scene_doc.is_object() || !scene_doc.contains("parameters") ||
      !scene_doc["parameters"].is_object())
    throw InputError("parameters", "expected an object of parameters", file);
  Json tree = Json::object();
  std::map<std::string, std::string> owner;  // leaf path -> the part that placed it
  place_parts(tree, owner, scene_doc, file, parts);
  merge_own(tree, owner, scene_doc["parameters"], file);
  resolve_catalogues(tree, "", file);
  return tree;
}

std::vector<std::string> parameter_catalogue(std::string_view name) {
  const Menu* m = find_menu(core_menus(), name);
  return m ? menu_names(*m) : std::vector<std::string>{};
}

std::vector<std::string> parameter_catalogue_names() {
  std::vector<std::string> out;
  for (const Menu& m : core_menus()) out.emplace_back(m.id);
  return out;
}

}  // namespace rodend
