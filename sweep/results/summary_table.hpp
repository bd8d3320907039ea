// The summary's table: its columns (name, unit, description, how a case record gives the value),
// a block of their values, and those values as lines of summary.csv. Written by summary.cpp,
// read back by summary_read.cpp.
#pragma once

#include <functional>
#include <set>
#include <string>
#include <vector>

#include "sweep/results.hpp"

namespace rodend::results_detail {

/// A summary column: name, unit, description and how a case record gives its value.
struct Column {
  enum class Kind { text, integer, real };
  std::string name, unit, description;
  Kind kind = Kind::real;
  std::function<std::string(const CaseRecord&)> text;
  std::function<long long(const CaseRecord&)> integer;
  std::function<double(const CaseRecord&)> real;
};

/// The values of one column for a block of rows (or for a whole table read back).
struct ColumnValues {
  Column::Kind kind = Column::Kind::real;
  std::vector<std::string> texts;
  std::vector<long long> integers;
  std::vector<double> reals;
  std::size_t size() const {
    return kind == Column::Kind::text      ? texts.size()
           : kind == Column::Kind::integer ? integers.size()
                                           : reals.size();
  }
};

/// The columns of the summary, in table order; `text_coordinates`: the grid keys whose values
/// are not all numbers (a text column; the others are numeric).
std::vector<Column> summary_columns(const Study& study,
                                    const std::set<std::string>& text_coordinates);
/// The values of column `c` for the records of `block`, into `out`.
void column_values(const Column& c, const std::vector<CaseRecord>& block, ColumnValues& out);
/// The header line of summary.csv: the column names.
std::string summary_csv_header(const std::vector<std::string>& names);
/// The first `rows` rows of `cols` as lines of summary.csv, appended to `text`: numbers as the
/// shortest decimal that reads back as the same double.
void append_summary_csv_rows(const std::vector<ColumnValues>& cols, std::size_t rows,
                             std::string& text);

/// Rows a summary is written in: the memory a summary takes is about this many case records.
constexpr std::size_t kSummaryRowsPerBlock = 256;

}  // namespace rodend::results_detail
