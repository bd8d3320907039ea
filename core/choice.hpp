// A choice from a fixed menu (run status, integrator method, contact-onset mode, friction law,
// contact geometry, damping cap, wear model) is an enum inside the program and a name only at
// its edges: the loader, the results, the schema and the docs.
//
// Each menu is one catalogue, an X-macro .def file (core/run_statuses.def,
// core/integrator_methods.def, core/contact_onsets.def, core/laws/friction_laws.def,
// core/contact_geometries.def, core/damping_caps.def, core/wear_models.def): one line per
// choice, from which come the enum's values, in order, and `choice_names(E{})` /
// `choice_descriptions(E{})`. Adding a choice is one line there (and its code). The templates
// below are the only place a name is compared with a string.
#pragma once

#include <concepts>
#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

namespace rodend {

/// An enum with a catalogue: choice_names(E{}) lists its names in the enum's order.
template <class E>
concept Choice = std::is_enum_v<E> && requires(E e) {
  { choice_names(e) } -> std::convertible_to<std::span<const std::string_view>>;
  { choice_descriptions(e) } -> std::convertible_to<std::span<const std::string_view>>;
};

/// The name of a choice ("unknown" for a value outside the catalogue).
template <Choice E>
std::string_view choice_name(E e) {
  const std::span<const std::string_view> names = choice_names(E{});
  const auto i = static_cast<std::size_t>(e);
  return i < names.size() ? names[i] : std::string_view("unknown");
}

/// The choice called `name`, or nullopt.
template <Choice E>
std::optional<E> choice_from_name(std::string_view name) {
  const std::span<const std::string_view> names = choice_names(E{});
  for (std::size_t i = 0; i < names.size(); ++i)
    if (names[i] == name) return static_cast<E>(i);
  return std::nullopt;
}

/// Every value of the catalogue, in its order.
template <Choice E>
std::vector<E> choice_values() {
  std::vector<E> out;
  for (std::size_t i = 0; i < choice_names(E{}).size(); ++i) out.push_back(static_cast<E>(i));
  return out;
}

/// The names as owned strings (for a list of allowed values: a schema's enum, a message).
template <Choice E>
std::vector<std::string> choice_strings() {
  const std::span<const std::string_view> names = choice_names(E{});
  return {names.begin(), names.end()};
}

/// "\"a\", \"b\" or \"c\"": the names quoted, for a message.
template <Choice E>
std::string choice_alternatives() {
  const std::span<const std::string_view> names = choice_names(E{});
  std::string out;
  for (std::size_t i = 0; i < names.size(); ++i)
    out += (i == 0                  ? ""
            : i + 1 == names.size() ? " or "
                                    : ", ") +
           ("\"" + std::string(names[i])) + "\"";
  return out;
}

/// "a, b, c": the names for a message.
template <Choice E>
std::string choice_list() {
  std::string out;
  for (std::string_view n : choice_names(E{})) out += (out.empty() ? "" : ", ") + std::string(n);
  return out;
}

}  // namespace rodend
