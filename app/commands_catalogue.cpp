// `rodend scenes`, `params`, `signals`, `metrics` and `choices`: the catalogues, as text,
// Markdown or JSON.
#include <iostream>
#include <memory>

#include "app/commands.hpp"
#include "core/integrator.hpp"
#include "core/scene.hpp"
#include "sweep/menus.hpp"
#include "sweep/study.hpp"

namespace rodend::cli {

namespace {

/// The flags of a listing: --markdown (when it has a Markdown form) and --json.
struct Format {
  bool markdown = false, json = false;
};

int list_params(const std::string& scene, bool json) {
  const ParameterSet p = ParameterSet::defaults_for(scene);
  if (json) {
    std::cout << p.leaves().dump(2) << "\n";
    return 0;
  }
  const Json leaves = p.leaves();
  for (const auto& [path, leaf] : leaves.items()) {
    std::cout << path << " = " << leaf["value"].dump() << " [" << leaf["unit"].get<std::string>()
              << "]  (" << leaf["source"].get<std::string>();
    if (leaf.contains("note")) std::cout << ": " << leaf["note"].get<std::string>();
    std::cout << ")\n";
  }
  return 0;
}

void list_signals(Format f) {
  if (f.json) {
    Json out = Json::array();
    for (const auto& s : signal_catalogue())
      out.push_back(
          {{"name", s.name}, {"unit", s.unit}, {"width", s.width}, {"description", s.description}});
    std::cout << out.dump(2) << "\n";
    return;
  }
  if (f.markdown) std::cout << "| signal | unit | width | description |\n|---|---|---|---|\n";
  for (const auto& s : signal_catalogue()) {
    if (f.markdown)
      std::cout << "| `" << s.name << "` | " << s.unit << " | " << s.width << " | " << s.description
                << " |\n";
    else
      std::cout << s.name << " [" << s.unit << "] x" << s.width << ": " << s.description << "\n";
  }
}

void list_metrics(Format f) {
  if (f.json) {
    Json out = Json::array();
    for (const auto& m : metric_catalogue())
      out.push_back({{"name", m.name}, {"unit", m.unit}, {"description", m.description}});
    std::cout << out.dump(2) << "\n";
    return;
  }
  if (f.markdown) std::cout << "| metric | unit | description |\n|---|---|---|\n";
  for (const auto& m : metric_catalogue()) {
    if (f.markdown)
      std::cout << "| `" << m.name << "` | " << m.unit << " | " << m.description << " |\n";
    else
      std::cout << m.name << " [" << m.unit << "]: " << m.description << "\n";
  }
}

/// One menu (core/menus.hpp) as a table or JSON: its choices' names and descriptions.
void print_menu(const Menu& menu, bool markdown, Json* json) {
  const std::vector<MenuItem> items = menu.items();
  if (json) {
    Json list = Json::array();
    for (const MenuItem& i : items)
      list.push_back({{"name", i.name}, {"description", i.description}});
    (*json)[std::string(menu.id)] = {{"title", menu.title}, {"keys", menu.keys}, {"choices", list}};
    return;
  }
  if (markdown)
    std::cout << "\n## " << menu.title << " (`" << menu.id << "`)\n\nTaken by " << menu.keys
              << ".\n\n| name | description |\n|---|---|\n";
  else
    std::cout << menu.title << " (" << menu.id << "; " << menu.keys << "):\n";
  for (const MenuItem& i : items)
    if (markdown)
      std::cout << "| `" << i.name << "` | " << i.description << " |\n";
    else
      std::cout << "  " << i.name << ": " << i.description << "\n";
}

/// `rodend choices`: every menu (core/menus.def, sweep/menus.def), with the keys that take it.
void list_choices(Format f) {
  Json out = Json::object();
  for (const Menu& m : all_menus()) print_menu(m, f.markdown, f.json ? &out : nullptr);
  if (f.json) std::cout << out.dump(2) << "\n";
}

/// A listing subcommand with --markdown (unless `markdown_help` is null) and --json.
CLI::App* listing(CLI::App& app, const char* name, const std::string& help,
                  const char* markdown_help, const std::shared_ptr<Format>& f) {
  CLI::App* c = app.add_subcommand(name, help);
  if (markdown_help) c->add_flag("--markdown", f->markdown, markdown_help);
  c->add_flag("--json", f->json, "as JSON");
  return c;
}

}  // namespace

void add_scenes(CLI::App& app, Outcome&) {
  app.add_subcommand("scenes", "List the scenes.")->callback([] {
    for (const auto& s : scene_catalogue()) std::cout << s.name << "\t" << s.summary << "\n";
  });
}

void add_params(CLI::App& app, Outcome& out) {
  auto scene = std::make_shared<std::string>();
  auto f = std::make_shared<Format>();
  CLI::App* c =
      app.add_subcommand("params", "Print a scene's default parameters with units and provenance.");
  c->add_option("SCENE", *scene, "scene name")->required();
  c->add_flag("--json", f->json, "as JSON");
  c->callback([scene, f, &out] { out.exit_code = list_params(*scene, f->json); });
}

void add_signals(CLI::App& app, Outcome&) {
  auto f = std::make_shared<Format>();
  listing(app, "signals", "Print the catalogue of recorded signals.", "as a Markdown table", f)
      ->callback([f] { list_signals(*f); });
}

void add_metrics(CLI::App& app, Outcome&) {
  auto f = std::make_shared<Format>();
  listing(app, "metrics", "Print the summary metrics.", "as a Markdown table", f)->callback([f] {
    list_metrics(*f);
  });
}

void add_choices(CLI::App& app, Outcome&) {
  auto f = std::make_shared<Format>();
  listing(app, "choices",
          "Print every menu of named choices (core/menus.def, sweep/menus.def): its names, what "
          "each means and the keys that take them.",
          "as Markdown tables", f)
      ->callback([f] { list_choices(*f); });
}

}  // namespace rodend::cli
