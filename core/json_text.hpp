// Words for JSON values in messages (the loaders of parameters and studies share them).
#pragma once

#include <nlohmann/json.hpp>
#include <string>

namespace rodend {

/// What a JSON value is, for messages: "a number", "an array of 3 numbers", "null".
std::string json_type_name(const nlohmann::json& j);

}  // namespace rodend
