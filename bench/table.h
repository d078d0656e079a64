// A result table written once and rendered two ways: aligned columns for the terminal
// and GitHub Markdown for the results document.
#pragma once
#include <string>
#include <vector>

namespace masq {

struct Table {
  std::string title;
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows; // short rows are padded with empty cells
  std::vector<std::string> notes;             // one line each, below the table
  int left_columns = 1;                       // leading columns aligned left (labels)

  void add(std::vector<std::string> row) { rows.push_back(std::move(row)); }
  std::string text() const;
  std::string markdown() const;
};

} // namespace masq
