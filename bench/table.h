// A result table written once and rendered two ways: aligned columns for the terminal
// and GitHub Markdown for the results document.
#pragma once
#include <nlohmann/json_fwd.hpp>
#include <string>
#include <vector>

namespace masq {

struct Table {
  std::string title;
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows; // short rows are padded with empty cells
  std::vector<std::string> notes;             // one line each, below the table
  int left_columns = 1;                       // leading columns aligned left (labels)
  // Leading columns that name a row (`masq report` matches rows across runs by them);
  // -1: the left_columns. Numbers that name a row are aligned right, so fig3 sets both.
  int label_columns = -1;

  int row_label_columns() const { return label_columns >= 0 ? label_columns : left_columns; }

  void add(std::vector<std::string> row) { rows.push_back(std::move(row)); }
  // Cell i of a row, "" past its end (short rows).
  static std::string cell(const std::vector<std::string>& row, std::size_t i) {
    return i < row.size() ? row[i] : std::string();
  }
  std::string text() const;
  std::string markdown() const;
};

// The table as JSON, {title, header, rows, notes, left_columns, label_columns (optional
// when reading: the left_columns)}: results.json keeps every
// suite's tables so that `masq report` can merge runs. from_json checks every field and
// throws masq::Error naming the bad one by its JSON pointer relative to the table
// ("/rows/2/0: not a string"), which the reader prefixes with the file and the table's place.
void to_json(nlohmann::json& j, const Table& t);
void from_json(const nlohmann::json& j, Table& t);

} // namespace masq
