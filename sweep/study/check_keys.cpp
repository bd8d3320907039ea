// Checking the keys of a study document as a whole: an object, nested a few levels, no NUL
// character, only the top-level keys a study has (study_keys).
#include <algorithm>
#include <optional>

#include "sweep/study/loader.hpp"

namespace rodend {

const std::vector<std::string>& study_keys() {
  static const std::vector<std::string> keys{
      "name",   "description", "scene", "parameters", "integrator",     "time",   "signals",
      "health", "metrics",     "grid",  "output",     "wear_evolution", "design", "sensors"};
  return keys;
}

}  // namespace rodend

namespace rodend::study_detail {

namespace {

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

}  // namespace

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

}  // namespace rodend::study_detail
