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

std::string record_field_text(const Features& v) {
  return Json(v.names()).dump();
}

void record_field_from_text(const std::string& text, Json& v) {
  v = Json::parse(text);
}

void record_field_from_text(const std::string& text, Features& v) {
  const Json names = Json::parse(text);
  if (!names.is_array()) throw std::runtime_error("features: expected a JSON array of names");
  const auto cat = feature_catalogue();
  v = Features{};
  for (const Json& n : names)
    for (std::size_t i = 0; i < cat.size(); ++i)
      if (n.is_string() && n.get<std::string>() == cat[i].name) v.set(static_cast<Feature>(i));
}

}  // namespace rodend
