// The loader's JSON helpers: a value of the expected type (or an InputError naming its key
// path), a document's nesting depth, nested keys flattened to dotted ones, a list of names.
#include <algorithm>
#include <cmath>

#include "core/json_text.hpp"
#include "sweep/study/loader.hpp"

namespace rodend::study_detail {

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

std::string alternatives(const std::vector<std::string>& names, bool quoted, const char* last) {
  std::string out;
  for (std::size_t i = 0; i < names.size(); ++i) {
    if (i > 0) out += i + 1 == names.size() ? last : ", ";
    out += quoted ? "\"" + names[i] + "\"" : names[i];
  }
  return out;
}

void flatten(const Json& node, const std::string& prefix,
             std::vector<std::pair<std::string, Json>>& out) {
  for (auto it = node.begin(); it != node.end(); ++it) {
    const std::string key = prefix.empty() ? it.key() : prefix + "." + it.key();
    // an empty object is a value, not an empty group: refused where a value goes, as --set
    // refuses it ({"sample_interval": {}} is not "unset")
    if (it->is_object() && !it->empty())
      flatten(*it, key, out);
    else
      out.emplace_back(key, *it);
  }
}

}  // namespace rodend::study_detail
