// The batch runner's menus (sweep/menus.def) after the core's.
#include "sweep/menus.hpp"

#include <iterator>
#include <vector>

#include "sweep/design.hpp"
#include "sweep/sensors.hpp"
#include "sweep/study.hpp"

namespace rodend {
namespace {

/// The default sensor sets (sweep/sensor_sets.def), each described by the sensors it holds.
std::vector<MenuItem> sensor_set_items() {
  std::vector<MenuItem> out;
  for (const std::string& set : sensor_set_names()) {
    std::string sensors;
    for (const std::string& s : sensor_set_members(set))
      sensors += (sensors.empty() ? "" : ", ") + s;
    out.push_back({set, "the sensors " + sensors});
  }
  return out;
}

constexpr Menu kSweepMenus[] = {
#define RODEND_MENU(id, title, keys, items) {#id, title, keys, &items},
#include "sweep/menus.def"
#undef RODEND_MENU
};

}  // namespace

std::span<const Menu> all_menus() {
  static const std::vector<Menu> all = [] {
    std::vector<Menu> v(core_menus().begin(), core_menus().end());
    v.insert(v.end(), std::begin(kSweepMenus), std::end(kSweepMenus));
    return v;
  }();
  return all;
}

}  // namespace rodend
