// The summary's columns and summary.csv's text (sweep/results/summary_table.hpp).
#include "sweep/results/summary_table.hpp"

#include <limits>
#include <stdexcept>

namespace rodend::results_detail {

std::vector<Column> summary_columns(const Study& study,
                                    const std::set<std::string>& text_coordinates) {
  std::vector<Column> cols;
  using Get = std::function<std::string(const CaseRecord&)>;
  auto text = [&](std::string name, std::string unit, std::string desc, Get get) {
    Column c{std::move(name), std::move(unit), std::move(desc), Column::Kind::text, {}, {}, {}};
    c.text = std::move(get);
    cols.push_back(std::move(c));
  };
  auto integer = [&](std::string name, std::string unit, std::string desc,
                     std::function<long long(const CaseRecord&)> get) {
    Column c{std::move(name), std::move(unit), std::move(desc), Column::Kind::integer, {}, {}, {}};
    c.integer = std::move(get);
    cols.push_back(std::move(c));
  };
  auto real = [&](std::string name, std::string unit, std::string desc,
                  std::function<double(const CaseRecord&)> get) {
    Column c{std::move(name), std::move(unit), std::move(desc), Column::Kind::real, {}, {}, {}};
    c.real = std::move(get);
    cols.push_back(std::move(c));
  };
  constexpr double nan = std::numeric_limits<double>::quiet_NaN();

  text("case_id", "", "case id: FNV-1a 64 hash of the canonical case description",
       [](const CaseRecord& r) { return r.id; });
  integer("case_index", "1", "position of the case in the expanded grid, 0-based",
          [](const CaseRecord& r) { return static_cast<long long>(r.index); });
  text("scene", "", "the case's scene (a grid coordinate when the study's scene is a grid axis)",
       [](const CaseRecord& r) { return r.scene; });

  // grid coordinates: numeric columns when every value is a number, else text (strings as
  // they are, other values as compact JSON); a missing value is NaN or ""
  for (const std::string& key : study.axis_keys) {
    if (key == "scene") continue;  // the scene column above
    std::string unit;
    if (key.rfind("parameters.", 0) == 0 && !study.cases.empty()) {
      const std::string path = key.substr(11);
      for (const CaseSpec& c : study.cases)  // with a scene axis, not every scene has it
        if (c.parameters.has(path)) {
          unit = c.parameters.unit(path);
          break;
        }
    }
    const std::string desc = "grid coordinate " + key;
    auto value = [key](const CaseRecord& r) -> const Json* {
      if (!r.coordinates.is_object()) return nullptr;
      const auto it = r.coordinates.find(key);
      return it == r.coordinates.end() ? nullptr : &*it;
    };
    if (text_coordinates.count(key) == 0)
      real(key, unit, desc, [value](const CaseRecord& r) {
        const Json* v = value(r);
        return v && v->is_number() ? v->get<double>() : nan;
      });
    else
      text(key, unit, desc, [value](const CaseRecord& r) {
        const Json* v = value(r);
        return !v ? std::string() : v->is_string() ? v->get<std::string>() : v->dump();
      });
  }

  text("status", "", "\"ok\" or the reason the run stopped",
       [](const CaseRecord& r) { return r.status; });
  text("message", "", "details of a failed run (empty when ok)",
       [](const CaseRecord& r) { return r.message; });
  real("t_reached_s", "s", "simulation time reached",
       [](const CaseRecord& r) { return r.t_reached; });
  real("wall_time_s", "s", "wall-clock time of the run",
       [](const CaseRecord& r) { return r.wall_time; });
  integer("steps_accepted", "1", "accepted integration steps",
          [](const CaseRecord& r) { return r.steps_accepted; });
  integer("steps_rejected", "1", "rejected integration steps",
          [](const CaseRecord& r) { return r.steps_rejected; });
  integer("rhs_calls", "1", "right-hand-side evaluations",
          [](const CaseRecord& r) { return r.rhs_calls; });
  text("started_utc", "", "start of the run, UTC, ISO 8601",
       [](const CaseRecord& r) { return r.started_utc; });
  text("finished_utc", "", "end of the run, UTC, ISO 8601",
       [](const CaseRecord& r) { return r.finished_utc; });

  const auto cat = metric_catalogue();
  for (std::size_t i = 0; i < cat.size() && i < MetricValues{}.size(); ++i)
    real(std::string(cat[i].name), std::string(cat[i].unit), std::string(cat[i].description),
         [i](const CaseRecord& r) { return r.metrics[i]; });

  std::set<std::string> seen;
  for (const Column& c : cols) {
    if (c.name.empty() || c.name.find('/') != std::string::npos || c.name == ".")
      throw std::runtime_error("summary column name \"" + c.name + "\" is not usable");
    if (!seen.insert(c.name).second)
      throw std::runtime_error("summary column \"" + c.name + "\" appears twice");
  }
  return cols;
}

/// The values of column `c` for the records of `block`, into `out`.
void column_values(const Column& c, const std::vector<CaseRecord>& block, ColumnValues& out) {
  out.kind = c.kind;
  out.texts.clear();
  out.integers.clear();
  out.reals.clear();
  for (const CaseRecord& r : block) switch (c.kind) {
      case Column::Kind::text:
        out.texts.push_back(c.text(r));
        break;
      case Column::Kind::integer:
        out.integers.push_back(c.integer(r));
        break;
      case Column::Kind::real:
        out.reals.push_back(c.real(r));
        break;
    }
}

namespace {

std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\n\r") == std::string::npos) return s;
  std::string out = "\"";
  for (const char ch : s) {
    if (ch == '"') out += '"';
    out += ch;
  }
  return out + "\"";
}

}  // namespace

std::string summary_csv_header(const std::vector<std::string>& names) {
  std::string text;
  for (std::size_t j = 0; j < names.size(); ++j) {
    if (j) text += ',';
    text += csv_field(names[j]);
  }
  return text + '\n';
}

/// The first `rows` rows of `cols` as lines of summary.csv, appended to `text`: numbers as the
/// shortest decimal that reads back as the same double.
void append_summary_csv_rows(const std::vector<ColumnValues>& cols, std::size_t rows,
                             std::string& text) {
  for (std::size_t i = 0; i < rows; ++i) {
    for (std::size_t j = 0; j < cols.size(); ++j) {
      const ColumnValues& c = cols[j];
      if (j) text += ',';
      switch (c.kind) {
        case Column::Kind::text:
          text += csv_field(c.texts[i]);
          break;
        case Column::Kind::integer:
          text += std::to_string(c.integers[i]);
          break;
        case Column::Kind::real:
          text += shortest_decimal(c.reals[i]);
          break;
      }
    }
    text += '\n';
  }
}

}  // namespace rodend::results_detail
