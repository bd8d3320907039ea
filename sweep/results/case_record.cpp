// The case record's catalogue (sweep/case_record.def) as a table.
#include <array>
#include <stdexcept>
#include <string>

#include "sweep/results.hpp"

namespace rodend {

std::span<const RecordFieldSpec> record_catalogue() {
  static constexpr std::array kFields{
#define RODEND_RECORD_FIELD(member, type, place, name, unit, description) \
  RecordFieldSpec{#member, name, unit, description, RecordType::type, RecordPlace::place},
#include "sweep/case_record.def"
#undef RODEND_RECORD_FIELD
  };
  return kFields;
}

}  // namespace rodend

namespace rodend {

std::string record_field_text(const Json& v) {
  return v.dump();
}

// Features as text without a Json value: destroying a non-empty Json array allocates
// (nlohmann::json 3.11), and an allocation failing in a destructor ends the process
// (cli.alloc_failures). The names are identifiers: nothing to escape.
std::string record_field_text(const Features& v) {
  std::string out = "[";
  for (const std::string_view name : v.names()) {
    if (out.size() > 1) out += ',';
    out.append("\"").append(name).append("\"");
  }
  return out + "]";
}

void record_field_from_text(const std::string& text, Json& v) {
  v = Json::parse(text);
}

void record_field_from_text(const std::string& text, Features& v) {
  const auto first = text.find_first_not_of(" \t\n\r");
  const auto last = text.find_last_not_of(" \t\n\r");
  if (first == std::string::npos || text[first] != '[' || text[last] != ']')
    throw std::runtime_error("features: expected a JSON array of names");
  const auto cat = feature_catalogue();
  v = Features{};
  std::size_t at = first + 1;
  while (at < last) {
    const std::size_t open = text.find('"', at);
    if (open == std::string::npos || open >= last) break;
    const std::size_t close = text.find('"', open + 1);
    if (close == std::string::npos || close >= last)
      throw std::runtime_error("features: expected a JSON array of names");
    const std::string_view name(text.data() + open + 1, close - open - 1);
    for (std::size_t i = 0; i < cat.size(); ++i)
      if (name == cat[i].name) v.set(static_cast<Feature>(i));
    at = close + 1;
  }
}

}  // namespace rodend
