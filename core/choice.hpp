// A choice from a fixed menu (run status, integrator method, contact-onset mode, friction law,
// friction mode, contact geometry, damping cap, wear model, history precision) is an enum inside
// the program and a name only at its edges: the loader, the results, the schema and the docs.
//
// Each menu is one catalogue, an X-macro .def file (core/run_statuses.def,
// core/integrator_methods.def, core/contact_onsets.def, core/laws/friction_laws.def,
// core/laws/friction_modes.def, core/contact_geometries.def, core/damping_caps.def,
// core/wear_models.def, sweep/history_precisions.def, core/linkage/beam_supports.def) of lines
//   RODEND_CHOICE(identifier, "name", "description"[, further columns of that catalogue])
// one per choice, in the enum's order. A header makes the catalogue's enum E, choice_names(E{})
// and choice_descriptions(E{}) in three lines, inside namespace rodend, by including this file
// again (its second part, below):
//   #define RODEND_CHOICE_ENUM RunStatus
//   #define RODEND_CHOICE_FILE "core/run_statuses.def"
//   #include "core/choice.hpp"
// The templates of the first part (name, parse, values, allowed names) then serve every
// catalogue. Adding a choice is one line of its .def (and its code); the templates are the only
// place a name is compared with a string.
#if defined(RODEND_CHOICE_ENUM) && !defined(RODEND_CORE_CHOICE_HPP)
#error "core/choice.hpp: include it at the top of the header before including it for a catalogue"
#endif

#ifndef RODEND_CORE_CHOICE_HPP
#define RODEND_CORE_CHOICE_HPP

#include <algorithm>
#include <concepts>
#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "core/edit_distance.hpp"

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

/// The name of a choice (the generic to_string of every catalogue's enum).
template <Choice E>
std::string_view to_string(E e) {
  return choice_name(e);
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

/// The name in `names` nearest to `name` by edit distance (Levenshtein), or "" when none is
/// within a third of the longer of the two (at least 2 edits): the "did you mean" of a message.
inline std::string_view nearest_name(std::span<const std::string_view> names,
                                     std::string_view name) {
  std::string_view best;
  std::size_t best_distance = 0;
  for (std::string_view n : names) {
    const std::size_t d = edit_distance(name, n);
    const std::size_t limit = std::max<std::size_t>(2, std::max(n.size(), name.size()) / 3);
    if (d <= limit && (best.empty() || d < best_distance)) best = n, best_distance = d;
  }
  return best;
}

/// "expected \"a\" or \"b\", got \"x\" (did you mean \"a\"?)": the message of a name that is not
/// in the catalogue (the did-you-mean only when a name is near).
template <Choice E>
std::string choice_expected(std::string_view got) {
  std::string out = "expected " + choice_alternatives<E>() + ", got \"" + std::string(got) + "\"";
  const std::string_view near = nearest_name(choice_names(E{}), got);
  if (!near.empty()) out += " (did you mean \"" + std::string(near) + "\"?)";
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

#endif  // RODEND_CORE_CHOICE_HPP

// The second part: one catalogue's enum and name tables, when a header includes this file with
// RODEND_CHOICE_ENUM (the enum's name) and RODEND_CHOICE_FILE (its .def) defined, inside
// namespace rodend (the first part included before, at the top of that header).
#ifdef RODEND_CHOICE_ENUM
#ifndef RODEND_CHOICE_FILE
#error "core/choice.hpp: RODEND_CHOICE_ENUM without RODEND_CHOICE_FILE (the catalogue's .def)"
#endif

/// The choices of RODEND_CHOICE_FILE, in its order.
enum class RODEND_CHOICE_ENUM {
#define RODEND_CHOICE(identifier, name, ...) identifier,
#include RODEND_CHOICE_FILE
#undef RODEND_CHOICE
};
inline std::span<const std::string_view> choice_names(RODEND_CHOICE_ENUM) {
  static constexpr std::string_view kNames[] = {
#define RODEND_CHOICE(identifier, name, ...) name,
#include RODEND_CHOICE_FILE
#undef RODEND_CHOICE
  };
  return kNames;
}
inline constexpr std::size_t choice_count(RODEND_CHOICE_ENUM) {
  return 0
#define RODEND_CHOICE(identifier, name, ...) +1
#include RODEND_CHOICE_FILE
#undef RODEND_CHOICE
      ;
}
inline std::span<const std::string_view> choice_descriptions(RODEND_CHOICE_ENUM) {
  static constexpr std::string_view kDescriptions[] = {
#define RODEND_CHOICE(identifier, name, description, ...) description,
#include RODEND_CHOICE_FILE
#undef RODEND_CHOICE
  };
  return kDescriptions;
}

#undef RODEND_CHOICE_ENUM
#undef RODEND_CHOICE_FILE
#endif  // RODEND_CHOICE_ENUM
