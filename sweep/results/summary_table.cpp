// The summary's columns and summary.csv's text (sweep/results/summary_table.hpp).
#include "sweep/results/summary_table.hpp"

#include <limits>
#include <stdexcept>
#include <type_traits>

namespace rodend::results_detail {

namespace {

/// Calls f(value) with field `i` of `r` (sweep/case_record.def).
template <class F>
void visit_record_field(const CaseRecord& r, std::size_t i, F&& f) {
  std::size_t k = 0;
  for_each_record_field(r, [&](const RecordFieldSpec&, const auto& v) {
    if (k++ == i) f(v);
  });
}

std::string as_text(const std::string& v) {
  return v;
}
template <class T>
std::string as_text(const T& v) {
  if constexpr (std::is_arithmetic_v<T>)
    return {};  // not a text column
  else
    return record_field_text(v);
}

/// The summary column of record field `i`: text, json and features fields as text, integers
/// as int64, reals as float64.
Column record_column(const RecordFieldSpec& f, std::size_t i) {
  Column c{std::string(f.name),
           std::string(f.unit),
           std::string(f.description),
           Column::Kind::text,
           {},
           {},
           {}};
  if (f.type == RecordType::integer) {
    c.kind = Column::Kind::integer;
    c.integer = [i](const CaseRecord& r) {
      long long out = 0;
      visit_record_field(r, i, [&](const auto& v) {
        if constexpr (std::is_same_v<std::decay_t<decltype(v)>, record_integer>) out = v;
      });
      return out;
    };
  } else if (f.type == RecordType::real) {
    c.kind = Column::Kind::real;
    c.real = [i](const CaseRecord& r) {
      double out = 0.0;
      visit_record_field(r, i, [&](const auto& v) {
        if constexpr (std::is_same_v<std::decay_t<decltype(v)>, record_real>) out = v;
      });
      return out;
    };
  } else {
    c.text = [i](const CaseRecord& r) {
      std::string out;
      visit_record_field(r, i, [&](const auto& v) { out = as_text(v); });
      return out;
    };
  }
  return c;
}

/// The unit of grid key `key`: a parameter's unit, from the first case that has it (with a
/// scene axis, not every scene has it); "" for other keys.
std::string coordinate_unit(const Study& study, const std::string& key) {
  if (key.rfind("parameters.", 0) != 0) return {};
  const std::string path = key.substr(11);
  for (const CaseSpec& c : study.cases)
    if (c.parameters.has(path)) return c.parameters.unit(path);
  return {};
}

/// The column of grid key `key`: numeric when every value is a number, else text (strings as
/// they are, other values as compact JSON); a missing value is NaN or "".
Column coordinate_column(const Study& study, const std::string& key, bool text) {
  Column c{key, coordinate_unit(study, key), "grid coordinate " + key, Column::Kind::real, {}, {},
           {}};
  auto value = [key](const CaseRecord& r) -> const Json* {
    if (!r.coordinates.is_object()) return nullptr;
    const auto it = r.coordinates.find(key);
    return it == r.coordinates.end() ? nullptr : &*it;
  };
  if (!text) {
    c.real = [value](const CaseRecord& r) {
      const Json* v = value(r);
      return v && v->is_number() ? v->get<double>() : std::numeric_limits<double>::quiet_NaN();
    };
  } else {
    c.kind = Column::Kind::text;
    c.text = [value](const CaseRecord& r) {
      const Json* v = value(r);
      return !v ? std::string() : v->is_string() ? v->get<std::string>() : v->dump();
    };
  }
  return c;
}

void check_column_names(const std::vector<Column>& cols) {
  std::set<std::string> seen;
  for (const Column& c : cols) {
    if (c.name.empty() || c.name.find('/') != std::string::npos || c.name == ".")
      throw std::runtime_error("summary column name \"" + c.name + "\" is not usable");
    if (!seen.insert(c.name).second)
      throw std::runtime_error("summary column \"" + c.name + "\" appears twice");
  }
}

}  // namespace

std::vector<Column> summary_columns(const Study& study,
                                    const std::set<std::string>& text_coordinates) {
  std::vector<Column> cols;
  const auto fields = record_catalogue();
  auto add_fields = [&](RecordPlace place) {
    for (std::size_t i = 0; i < fields.size(); ++i)
      if (fields[i].place == place) cols.push_back(record_column(fields[i], i));
  };
  add_fields(RecordPlace::identity);
  for (const std::string& key : study.axis_keys)
    if (key != "scene")  // the record's scene column
      cols.push_back(coordinate_column(study, key, text_coordinates.count(key) > 0));
  add_fields(RecordPlace::run);
  const auto cat = metric_catalogue();
  for (std::size_t i = 0; i < cat.size() && i < MetricValues{}.size(); ++i) {
    Column c{std::string(cat[i].name),
             std::string(cat[i].unit),
             std::string(cat[i].description),
             Column::Kind::real,
             {},
             {},
             {}};
    c.real = [i](const CaseRecord& r) { return r.metrics[i]; };
    cols.push_back(std::move(c));
  }
  check_column_names(cols);
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
