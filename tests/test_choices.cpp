// The catalogues of choices (core/choice.hpp, issue 32): each enum and its names come from one
// .def file; a name read back gives its enum, the names stored in results files by earlier
// versions are unchanged, and the scene parameters offer exactly the catalogue's names.
#include <catch2/catch.hpp>
#include <set>
#include <string>

#include "core/contact.hpp"
#include "core/integrator.hpp"
#include "core/menus.hpp"
#include "core/params.hpp"
#include "core/presets.hpp"
#include "core/scene.hpp"
#include "core/scene_parameters.hpp"
#include "core/scenes/drivers.hpp"
#include "core/scenes/impact_pair.hpp"
#include "core/scenes/parts.hpp"
#include "core/scenes/planar_slider_crank_options.hpp"
#include "core/scenes/profile.hpp"
#include "core/scenes/servo_actuator.hpp"
#include "core/wear.hpp"
#include "sweep/menus.hpp"
#include "sweep/study.hpp"

using namespace rodend;

namespace {

template <Choice E>
void check_catalogue() {
  const auto names = choice_names(E{});
  const auto descriptions = choice_descriptions(E{});
  REQUIRE(!names.empty());
  REQUIRE(descriptions.size() == names.size());
  const std::set<std::string_view> unique(names.begin(), names.end());
  CHECK(unique.size() == names.size());
  for (std::size_t i = 0; i < names.size(); ++i) {
    const auto e = static_cast<E>(i);
    CAPTURE(names[i]);
    CHECK(choice_name(e) == names[i]);
    CHECK(choice_from_name<E>(names[i]) == e);
    CHECK(!descriptions[i].empty());
  }
  CHECK(choice_values<E>().size() == names.size());
  CHECK_FALSE(choice_from_name<E>("no-such-choice"));
  CHECK_FALSE(choice_from_name<E>(""));
}

}  // namespace

TEST_CASE("every catalogue of choices: unique names, each read back as its enum", "[choices]") {
  check_catalogue<RunStatus>();
  check_catalogue<IntegratorMethod>();
  check_catalogue<ContactOnset>();
  check_catalogue<FrictionLawKind>();
  check_catalogue<FrictionMode>();
  check_catalogue<ContactGeometry>();
  check_catalogue<DampingCap>();
  check_catalogue<WearModelKind>();
  check_catalogue<IntegratorPreset>();
  check_catalogue<ParameterSource>();
  check_catalogue<WaveformKind>();
  check_catalogue<MotionShape>();
  check_catalogue<HingeMomentKind>();
  check_catalogue<ProfileInterpolation>();
  check_catalogue<ProfilePastEnd>();
  check_catalogue<TorqueMotor>();
  check_catalogue<LoadKind>();
  check_catalogue<LoadFrame>();
  check_catalogue<OuterBody>();
  check_catalogue<JointModel>();
  check_catalogue<RodModel>();
  check_catalogue<GuideModel>();
  check_catalogue<DriveModel>();
  check_catalogue<HistoryPrecision>();
}

TEST_CASE("every menu is one line of the catalogue of menus, listed by rodend choices",
          "[choices]") {
  std::set<std::string_view> ids;
  for (const Menu& m : all_menus()) {
    CAPTURE(m.id);
    CHECK(ids.insert(m.id).second);
    CHECK(!m.title.empty());
    CHECK(!m.keys.empty());
    const std::vector<MenuItem> items = m.items();
    REQUIRE(!items.empty());
    std::set<std::string> names;
    for (const MenuItem& i : items) {
      CHECK(names.insert(i.name).second);
      CHECK(!i.description.empty());
    }
  }
  // the 29 of the core, then the batch runner's 4 (history precisions, sensor sets, design
  // methods, distributions)
  CHECK(core_menus().size() == 29);
  CHECK(all_menus().size() == 33);
  // the menus scene files name: each leaf's catalogue resolves to the menu's names
  CHECK(parameter_catalogue("outer_bodies") == std::vector<std::string>{"fixed", "free"});
  CHECK(parameter_catalogue("normal_laws").size() == normal_laws().size());
  CHECK(parameter_catalogue("no_such_menu").empty());
  const Menu* sets = find_menu(all_menus(), "sensor_sets");
  REQUIRE(sets);
  CHECK(menu_names(*sets) == std::vector<std::string>{"typical"});
}

TEST_CASE("the waveforms are one list inside both menus that offer them", "[choices]") {
  const std::size_t n = choice_count(WaveformKind{});
  CHECK(choice_count(MotionShape{}) == 4 + n);
  CHECK(choice_count(HingeMomentKind{}) == 4 + n);
  for (WaveformKind w : choice_values<WaveformKind>()) {
    CAPTURE(choice_name(w));
    const auto i = static_cast<std::size_t>(w);
    CHECK(choice_names(MotionShape{})[3 + i] == choice_name(w));
    CHECK(choice_names(HingeMomentKind{})[3 + i] == choice_name(w));
    // the class of its line: sine and triangle have one frequency (a periodic input)
    const ParameterSet p = ParameterSet::defaults_for("servo-actuator");
    const bool periodic = make_input(w, InputKeys{p, "command"})->periodic().has_value();
    CHECK(periodic == (w == WaveformKind::sine || w == WaveformKind::triangle));
  }
}

TEST_CASE("an unknown name: the key, the menu's names and the nearest one", "[choices]") {
  CHECK(nearest_name(choice_names(JointModel{}), "clearence") == "clearance");
  CHECK(nearest_name(choice_names(JointModel{}), "welded").empty());
  CHECK(choice_expected<OuterBody>("fre") ==
        "expected \"fixed\" or \"free\", got \"fre\" (did you mean \"free\"?)");
  ParameterSet p = ParameterSet::defaults_for("impact-pair");
  REQUIRE_THROWS_WITH(p.set("impact.outer_body", "fre"), Catch::Contains("impact.outer_body"));
  // a leaf without a list of choices: the reader's own message
  const ParameterSet q = ParameterSet::from_json(
      Json::parse(R"({"guide": {"model": {"value": "idael", "unit": "1", "source": "assumed",
                                          "note": "a misspelt name"}}})"),
      "test");
  REQUIRE_THROWS_WITH(read_choice<GuideModel>(q, "guide.model"),
                      Catch::Contains("guide.model") &&
                          Catch::Contains("expected \"ideal\" or \"clearance\", got \"idael\" "
                                          "(did you mean \"ideal\"?)"));
}

TEST_CASE("the names of choices are those studies and results files use", "[choices]") {
  // results files and studies written before the catalogues hold these names: they must read
  CHECK(choice_strings<RunStatus>() ==
        std::vector<std::string>{"ok", "step_budget_exhausted", "rhs_budget_exhausted",
                                 "step_size_underflow", "non_finite_state", "penetration_limit",
                                 "energy_residual_limit", "actuator_saturation", "internal_error"});
  CHECK(choice_strings<IntegratorMethod>() ==
        std::vector<std::string>{"rk4", "dopri5", "cash_karp54", "fehlberg78", "bulirsch_stoer",
                                 "rosenbrock4", "cvode_bdf", "cvode_adams", "cvode_bdf3"});
  CHECK(choice_strings<ContactOnset>() == std::vector<std::string>{"locate", "step-end"});
  CHECK(choice_strings<FrictionLawKind>() ==
        std::vector<std::string>{"thesis", "ambrosio", "coulomb", "none"});
  CHECK(choice_strings<FrictionMode>() ==
        std::vector<std::string>{"smooth", "stick-slip", "switch"});
  CHECK(choice_strings<ContactGeometry>() == std::vector<std::string>{"sphere", "cylinder"});
  CHECK(choice_strings<DampingCap>() == std::vector<std::string>{"none", "elastic"});
  CHECK(choice_strings<WearModelKind>() == std::vector<std::string>{"none", "archard"});
  // the defaults are the first of their menus where the structs say so
  CHECK(IntegratorSettings{}.method == IntegratorMethod::dopri5);
  CHECK(IntegratorSettings{}.contact_onset == ContactOnset::locate);
  CHECK(fixed_step(IntegratorMethod::rk4));
  CHECK_FALSE(fixed_step(IntegratorMethod::dopri5));
  CHECK(choice_alternatives<ContactGeometry>() == "\"sphere\" or \"cylinder\"");
}

TEST_CASE("scene parameters offer exactly the catalogues' names", "[choices]") {
  const Json leaves = ParameterSet::defaults_for("rod-end-kinematic").leaves();
  auto choices = [&](const char* key) {
    return leaves.at(key).at("choices").get<std::vector<std::string>>();
  };
  CHECK(choices("wear.model") == choice_strings<WearModelKind>());
  CHECK(choices("friction.law") == choice_strings<FrictionLawKind>());
  CHECK(choices("friction.mode") == choice_strings<FrictionMode>());
  CHECK(choices("contact.geometry") == choice_strings<ContactGeometry>());
  CHECK(choices("contact.damping_cap") == choice_strings<DampingCap>());
}

TEST_CASE("an unknown choice in a scene parameter names the key", "[choices]") {
  // refused when set (the leaf's choices) or, at the latest, when the scene reads it
  auto build = [] {
    ParameterSet p = ParameterSet::defaults_for("rod-end-kinematic");
    p.set("wear.model", "paris");
    return make_scene("rod-end-kinematic", p);
  };
  REQUIRE_THROWS_WITH(build(), Catch::Contains("wear.model"));
}
