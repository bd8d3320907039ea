// Scene features: the catalogue (features.def) as an enum, a table and a set.
#pragma once

#include <cstdint>
#include <initializer_list>
#include <span>
#include <string_view>
#include <vector>

namespace rodend {

enum class Feature : int {
#define RODEND_FEATURE(id, doc) id,
#include "core/features.def"
#undef RODEND_FEATURE
  count_
};

inline constexpr int feature_count = static_cast<int>(Feature::count_);

/// One row of the catalogue.
struct FeatureSpec {
  std::string_view name;
  std::string_view description;
};

std::span<const FeatureSpec> feature_catalogue();

/// What a scene has (Scene::features()): a set of catalogue features.
class Features {
 public:
  constexpr Features() = default;
  constexpr Features(std::initializer_list<Feature> features) {
    for (Feature f : features) set(f);
  }
  constexpr bool has(Feature f) const { return (bits_ & bit(f)) != 0; }
  constexpr Features& set(Feature f, bool on = true) {
    bits_ = on ? (bits_ | bit(f)) : (bits_ & ~bit(f));
    return *this;
  }
  constexpr bool operator==(const Features&) const = default;
  /// The names of the features present, in catalogue order.
  std::vector<std::string_view> names() const;

 private:
  static constexpr std::uint32_t bit(Feature f) { return std::uint32_t{1} << static_cast<int>(f); }
  std::uint32_t bits_ = 0;
};
static_assert(feature_count <= 32, "Features holds at most 32 features");

}  // namespace rodend
