#include "core/features.hpp"

#include <array>

namespace rodend {
namespace {

constexpr std::array<FeatureSpec, feature_count> kCatalogue{{
#define RODEND_FEATURE(id, doc) FeatureSpec{#id, doc},
#include "core/features.def"
#undef RODEND_FEATURE
}};

}  // namespace

std::span<const FeatureSpec> feature_catalogue() {
  return kCatalogue;
}

std::vector<std::string_view> Features::names() const {
  std::vector<std::string_view> out;
  for (int i = 0; i < feature_count; ++i)
    if (has(static_cast<Feature>(i))) out.push_back(kCatalogue[static_cast<std::size_t>(i)].name);
  return out;
}

}  // namespace rodend
