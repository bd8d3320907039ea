// Parameter sets: the embedded defaults of every scene, the form of every leaf (unit and
// provenance), overrides by key path, and the physical checks made when a scene is built.
#include <algorithm>
#include <array>
#include <catch2/catch.hpp>
#include <functional>
#include <string>

#include "core/params.hpp"
#include "core/scene.hpp"
#include "core/scene_parameters.hpp"
#include "fixture.hpp"

using namespace rodend;

namespace {

InputError thrown_input_error(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e;
  }
  FAIL("expected an InputError");
  return InputError("", "");
}

std::vector<std::string> scene_names() {
  std::vector<std::string> names;
  for (const SceneEntry& e : scene_catalogue()) names.emplace_back(e.name);
  return names;
}

}  // namespace

TEST_CASE("every scene's embedded defaults parse and build", "[params]") {
  const auto names = scene_names();
  REQUIRE(names.size() >= 3);
  for (const std::string& scene : names) {
    CAPTURE(scene);
    // the document itself: names its scene and holds a parameter tree
    const Json doc = Json::parse(scene_default_parameters_json(scene));
    CHECK(doc.at("scene") == scene);
    CHECK(doc.at("parameters").is_object());
    ParameterSet p;
    REQUIRE_NOTHROW(p = ParameterSet::defaults_for(scene));
    CHECK_FALSE(p.paths().empty());
    CHECK_NOTHROW(make_scene(scene, p));
  }
}

TEST_CASE("every leaf has a unit and a provenance, and non-thesis leaves a note", "[params]") {
  for (const std::string& scene : scene_names()) {
    const ParameterSet p = ParameterSet::defaults_for(scene);
    const Json leaves = p.leaves();
    for (auto it = leaves.begin(); it != leaves.end(); ++it) {
      const std::string path = it.key();
      const Json& leaf = it.value();
      CAPTURE(scene, path);
      REQUIRE(leaf.contains("unit"));
      REQUIRE(leaf["unit"].is_string());
      CHECK_FALSE(leaf["unit"].get<std::string>().empty());  // "1" when dimensionless
      CHECK(p.unit(path) == leaf["unit"].get<std::string>());
      REQUIRE(leaf.contains("source"));
      const std::string source = leaf["source"].get<std::string>();
      CHECK((source == "thesis" || source == "assumed" || source == "derived"));
      if (source != "thesis") {
        REQUIRE(leaf.contains("note"));
        CHECK_FALSE(leaf["note"].get<std::string>().empty());
      }
      // numbers are finite, and string leaves with choices hold one of them
      const Json& v = leaf["value"];
      if (v.is_number()) CHECK(std::isfinite(v.get<double>()));
      if (v.is_string() && leaf.contains("choices"))
        CHECK(std::find(leaf["choices"].begin(), leaf["choices"].end(), v) !=
              leaf["choices"].end());
    }
  }
}

TEST_CASE("the parser rejects malformed leaves with their key path", "[params]") {
  const Json good = {{"ball", {{"mass", {{"value", 0.2}, {"unit", "kg"}, {"source", "thesis"}}}}}};
  CHECK_NOTHROW(ParameterSet::from_json(good, "test.json"));

  Json no_unit = good;
  no_unit["ball"]["mass"].erase("unit");
  InputError e = thrown_input_error([&] { ParameterSet::from_json(no_unit, "test.json"); });
  CHECK(e.key_path() == "ball.mass.unit");
  CHECK(e.file() == "test.json");

  Json bad_source = good;
  bad_source["ball"]["mass"]["source"] = "guessed";
  e = thrown_input_error([&] { ParameterSet::from_json(bad_source, "test.json"); });
  CHECK(e.key_path() == "ball.mass.source");

  Json assumed_without_note = good;
  assumed_without_note["ball"]["mass"]["source"] = "assumed";
  e = thrown_input_error([&] { ParameterSet::from_json(assumed_without_note, "test.json"); });
  CHECK(e.key_path() == "ball.mass.note");

  Json bad_value = good;
  bad_value["ball"]["mass"]["value"] = Json::array({"a", "b"});
  e = thrown_input_error([&] { ParameterSet::from_json(bad_value, "test.json"); });
  CHECK(e.key_path() == "ball.mass.value");
}

TEST_CASE("an unknown key is an InputError naming the key", "[params]") {
  ParameterSet p = ParameterSet::defaults_for("gravity-drop");
  for (const std::string key :
       {"contact.clearence", "nonsense", "ball.mass.value", "ball", "contact.clearance.extra"}) {
    CAPTURE(key);
    const InputError e = thrown_input_error([&] { p.set(key, 1.0); });
    CHECK(e.key_path() == key);
    CHECK_FALSE(p.has(key));
    CHECK(thrown_input_error([&] { (void)p.number(key); }).key_path() == key);
  }
  CHECK(p.has("contact.clearance"));
}

TEST_CASE("a value of the wrong type is an InputError naming the key", "[params]") {
  ParameterSet p = ParameterSet::defaults_for("gravity-drop");
  struct Bad {
    std::string key;
    Json value;
  };
  const std::vector<Bad> cases{
      {"ball.mass", "heavy"},                  // string for a number
      {"ball.mass", Json::array({0.1, 0.2})},  // array for a number
      {"ball.mass", true},                     // boolean for a number
      {"gravity", 9.81},                       // number for a vector
      {"gravity", Json::array({0.0, -9.81})},  // wrong length
      {"contact.law", 3},                      // number for a string
      {"contact.law", "newtonian"},            // string outside the choices
  };
  for (const Bad& b : cases) {
    CAPTURE(b.key, b.value.dump());
    const InputError e = thrown_input_error([&] { p.set(b.key, b.value); });
    CHECK(e.key_path() == b.key);
  }
  // and the rejected values left the set unchanged
  CHECK(p.number("ball.mass") == 0.2);
  CHECK(p.text("contact.law") == "lankarani-nikravesh");
  // a value of the right type is taken
  p.set("ball.mass", 0.25);
  CHECK(p.number("ball.mass") == 0.25);
}

TEST_CASE("non-physical values are rejected when the scene is built", "[params]") {
  struct Bad {
    std::string scene, key;
    double value;
  };
  const auto b = GENERATE(
      Bad{"gravity-drop", "ball.mass", 0.0}, Bad{"gravity-drop", "ball.mass", -0.2},
      Bad{"gravity-drop", "contact.clearance", 0.0},
      Bad{"gravity-drop", "contact.clearance", -1e-4},
      Bad{"gravity-drop", "contact.ball_radius", 0.0},
      Bad{"gravity-drop", "contact.restitution", 1.5},
      Bad{"gravity-drop", "contact.ball_poisson_ratio", 0.5},
      Bad{"gravity-drop", "contact.min_impact_speed", 0.0}, Bad{"spring-contact", "ball.mass", 0.0},
      Bad{"spring-contact", "socket.mass", -1.0}, Bad{"spring-contact", "contact.clearance", 0.0},
      Bad{"spring-contact", "tether.stiffness", -1.0}, Bad{"free-body", "body.mass", 0.0});
  CAPTURE(b.scene, b.key, b.value);
  ParameterSet p = ParameterSet::defaults_for(b.scene);
  REQUIRE_NOTHROW(make_scene(b.scene, p));
  p.set(b.key, b.value);  // the type is right: only the physics is wrong
  const InputError e = thrown_input_error([&] { make_scene(b.scene, p); });
  CHECK(e.key_path() == b.key);
}

TEST_CASE("unknown scenes are an InputError", "[params]") {
  CHECK(thrown_input_error([] { (void)ParameterSet::defaults_for("no-such-scene"); }).key_path() ==
        "scene");
  CHECK(thrown_input_error([] { make_scene("no-such-scene", ParameterSet{}); }).key_path() ==
        "scene");
}

TEST_CASE("scene files compose their parts; overrides keep unit and provenance", "[params]") {
  // two parts and a scene that places one twice, overrides a leaf by value only and another
  // with a note, and adds a leaf of its own
  const std::string mass = R"({"value": 0.2, "unit": "kg", "source": "thesis"})";
  const std::string law =
      R"({"value": "hertz", "unit": "1", "source": "thesis", "catalogue": "normal_laws"})";
  const std::string body_part = R"({"part": "body", "parameters": {"mass": )" + mass + "}}";
  const std::string contact_part = R"({"part": "contact", "parameters": {"law": )" + law + "}}";
  const std::array<EmbeddedJson, 2> parts{EmbeddedJson{"body", body_part},
                                          EmbeddedJson{"contact", contact_part}};
  Json doc = Json::parse(R"({"scene": "s", "parts": [{"part": "body", "at": "ball"},
      {"part": "body", "at": "outer"}, {"part": "contact", "at": "contact"}],
      "parameters": {"ball": {"mass": {"value": 0.25}},
                     "outer": {"mass": {"value": 0.3, "source": "assumed", "note": "housing"}},
                     "gravity": {"value": [0, -9.81, 0], "unit": "m/s^2", "source": "thesis"}}})");
  const ParameterSet p =
      ParameterSet::from_json(compose_scene_parameters(doc, "s.json", parts), "s");
  CHECK(p.paths() == std::vector<std::string>{"ball.mass", "contact.law", "gravity", "outer.mass"});
  const Json leaves = p.leaves();
  CHECK(leaves["ball.mass"] == Json::parse(R"({"value": 0.25, "unit": "kg", "source": "thesis"})"));
  CHECK(leaves["outer.mass"]["source"] == "assumed");
  CHECK(leaves["outer.mass"]["unit"] == "kg");
  // the catalogue's names become the leaf's choices, in the catalogue's order
  std::vector<std::string> names;
  for (const NormalLaw* l : normal_laws()) names.emplace_back(l->name());
  CHECK(leaves["contact.law"]["choices"].get<std::vector<std::string>>() == names);
  CHECK_FALSE(leaves["contact.law"].contains("catalogue"));

  struct Bad {
    const char* what;
    std::function<void(Json&)> edit;
    std::string key;
  };
  const std::vector<Bad> bad{
      {"unknown part", [](Json& d) { d["parts"][1]["part"] = "bdy"; }, "parts[1].part"},
      {"same part twice at one key", [](Json& d) { d["parts"][1]["at"] = "ball"; }, "ball.mass"},
      {"override changes the unit", [](Json& d) { d["parameters"]["ball"]["mass"]["unit"] = "g"; },
       "ball.mass.unit"},
      {"override changes the type",
       [](Json& d) { d["parameters"]["ball"]["mass"]["value"] = "heavy"; }, "ball.mass.value"},
      {"value only, for a key no part defines",
       [](Json& d) {
         d["parameters"]["ball"]["radius"] = {{"value", 0.01}};
       },
       "ball.radius"},
      {"leaf inside a part's leaf",
       [](Json& d) {
         d["parameters"]["ball"]["mass"] = {
             {"x", {{"value", 1}, {"unit", "1"}, {"source", "thesis"}}}};
       },
       "ball.mass.x"},
      {"leaf over a part's group",
       [](Json& d) {
         d["parameters"].erase("ball");
         d["parameters"]["outer"] = {{"value", 1}, {"unit", "1"}, {"source", "thesis"}};
       },
       "outer"},
      {"unknown catalogue",
       [](Json& d) {
         d["parameters"]["contact"]["law"] = {{"value", "hertz"}, {"catalogue", "laws"}};
       },
       "contact.law.catalogue"},
      {"unknown key in a part entry", [](Json& d) { d["parts"][0]["under"] = "x"; },
       "parts[0].under"},
  };
  for (const Bad& b : bad) {
    CAPTURE(b.what);
    Json d = doc;
    b.edit(d);
    const InputError e = thrown_input_error([&] {
      (void)ParameterSet::from_json(compose_scene_parameters(d, "s.json", parts), "s.json");
    });
    CHECK(e.key_path() == b.key);
    CHECK(e.file() == "s.json");
  }
}

TEST_CASE("scene and part files name catalogues instead of copying them", "[params]") {
  // a "choices" list equal to a catalogue is a copy: the file names the catalogue instead
  std::vector<std::vector<std::string>> catalogues;
  for (const std::string& c : parameter_catalogue_names())
    catalogues.push_back(parameter_catalogue(c));
  std::vector<std::pair<std::string, Json>> files;
  for (const EmbeddedJson& p : embedded_part_files())
    files.emplace_back(std::string(p.first) + ".part.json", Json::parse(p.second));
  for (const std::string& s : scene_names())
    files.emplace_back(s + ".params.json", Json::parse(scene_default_parameters_json(s)));
  CHECK(files.size() > scene_names().size());
  for (const auto& [file, doc] : files) {
    CAPTURE(file);
    const Json flat = doc.at("parameters").flatten();
    for (auto it = flat.begin(); it != flat.end(); ++it) {
      if (it.key().find("/choices/") == std::string::npos) continue;
      const std::string leaf = it.key().substr(0, it.key().find("/choices/"));
      const auto choices = doc.at("parameters")[Json::json_pointer(leaf + "/choices")]
                               .get<std::vector<std::string>>();
      CAPTURE(leaf);
      CHECK(std::find(catalogues.begin(), catalogues.end(), choices) == catalogues.end());
    }
  }
}

namespace {

/// What a feature means in signals: those every scene with it writes and no scene without it
/// writes (`own`), and those a scene with it writes besides (`also`).
struct FeatureSignals {
  std::vector<SignalId> own, also;
};

FeatureSignals feature_signals(Feature f) {
  using S = SignalId;
  switch (f) {
    case Feature::contact:
      return {
          {S::eccentricity, S::penetration, S::penetration_rate, S::impact_speed, S::contact_force},
          {}};
    case Feature::mechanism:
      // surface_rate is not the mechanism's own: the planar slider-crank writes its crank's
      // rate there; nor are surface_angle and surface_angle_command: the planar linkage writes
      // its shaft's angle and its ideal twin's there
      return {{S::hinge_moment},
              {S::surface_angle, S::surface_angle_command, S::actuator_position, S::surface_rate}};
    case Feature::actuator:
      return {{S::actuator_command, S::spool_position, S::chamber_pressures},
              {S::actuator_position}};
    case Feature::wear:
      return {{S::sliding_work, S::worn_volume}, {}};
    case Feature::planar:
      return {};  // no signal of its own: it says which components stay zero
    case Feature::energy_audit:
      return {{S::input_work, S::dissipated_energy, S::energy_residual}, {S::mechanical_energy}};
    case Feature::count_:
      break;
  }
  FAIL("feature " << static_cast<int>(f) << " has no entry in feature_signals");
  return {};
}

}  // namespace

TEST_CASE("every scene declares its features, and they agree with what it writes", "[params]") {
  std::vector<std::pair<std::string, ParameterSet>> variants;
  for (const std::string& scene : scene_names()) {
    ParameterSet p = ParameterSet::defaults_for(scene);
    variants.emplace_back(scene, p);
    if (p.has("wear.model")) {  // the same scene with wear
      p.set("wear.model", "archard");
      variants.emplace_back(scene + " (wear.model archard)", p);
    }
  }
  int with_wear = 0;
  for (const auto& [label, p] : variants) {
    const std::string scene = label.substr(0, label.find(' '));
    CAPTURE(label);
    const auto s = make_scene(scene, p);
    const Features has = s->features();
    const auto sig = s->signals();
    auto writes = [&](SignalId id) { return std::find(sig.begin(), sig.end(), id) != sig.end(); };
    for (std::size_t i = 0; i < feature_catalogue().size(); ++i) {
      const auto f = static_cast<Feature>(i);
      CAPTURE(feature_catalogue()[i].name);
      const FeatureSignals fs = feature_signals(f);
      for (SignalId id : fs.own) {
        CAPTURE(signal_spec(id).name);
        CHECK(writes(id) == has.has(f));
      }
      if (has.has(f))
        for (SignalId id : fs.also) {
          CAPTURE(signal_spec(id).name);
          CHECK(writes(id));
        }
    }
    // what the driver and the wear bookkeeping ask of the scene itself
    CHECK((s->contact_count() > 0) == has.has(Feature::contact));
    CHECK((s->wear_model() != nullptr) == has.has(Feature::wear));
    // the audit's time integrals (input work and/or dissipation) are states of the scene
    if (has.has(Feature::energy_audit)) CHECK_FALSE(s->audit_offsets().empty());
    with_wear += has.has(Feature::wear) ? 1 : 0;
  }
  CHECK(with_wear == 2);  // rod-end-kinematic and rod-end-actuator with wear.model archard
  // as declared (scenes.def): the mechanism scenes, the actuator scenes
  CHECK(
      make_scene("rod-end-actuator", ParameterSet::defaults_for("rod-end-actuator"))->features() ==
      Features{Feature::contact, Feature::mechanism, Feature::actuator, Feature::energy_audit});
  CHECK(make_scene("free-body", ParameterSet::defaults_for("free-body"))->features() ==
        Features{Feature::energy_audit});
}
