#include "bench/table.h"
#include "bench/json_field.h"
#include "masq/error.h"
#include <algorithm>

namespace masq {

std::string Table::text() const {
  std::vector<std::size_t> width(header.size());
  for (std::size_t i = 0; i < header.size(); ++i) {
    width[i] = header[i].size();
    for (const auto& r : rows) width[i] = std::max(width[i], cell(r, i).size());
  }
  auto line = [&](const std::vector<std::string>& r) {
    std::string out;
    for (std::size_t i = 0; i < header.size(); ++i) {
      std::string c = cell(r, i);
      std::string pad(width[i] - std::min(width[i], c.size()), ' ');
      out += (i ? "  " : "") + (int(i) < left_columns ? c + pad : pad + c);
    }
    while (!out.empty() && out.back() == ' ') out.pop_back();
    return out + "\n";
  };
  std::string out = title.empty() ? "" : title + "\n";
  out += line(header);
  for (const auto& r : rows) out += line(r);
  for (const auto& n : notes) out += n + "\n";
  return out;
}

std::string Table::markdown() const {
  auto esc = [](std::string c) {
    std::string o;
    for (char ch : c) o += ch == '|' ? std::string("\\|") : std::string(1, ch);
    return o;
  };
  std::string out = title.empty() ? "" : "**" + title + "**\n\n";
  out += "|";
  // Appends rather than " " + s: GCC 12 reports a false -Wrestrict on that operator+.
  for (const auto& h : header) out.append(" ").append(esc(h)).append(" |");
  out += "\n|";
  for (std::size_t i = 0; i < header.size(); ++i) out += int(i) < left_columns ? "---|" : "---:|";
  out += "\n";
  for (const auto& r : rows) {
    out += "|";
    for (std::size_t i = 0; i < header.size(); ++i) out.append(" ").append(esc(cell(r, i))).append(" |");
    out += "\n";
  }
  if (!notes.empty()) out += "\n";
  for (const auto& n : notes) out += n + "\n";
  return out;
}

void to_json(nlohmann::json& j, const Table& t) {
  j = {{"title", t.title}, {"header", t.header}, {"rows", t.rows}, {"notes", t.notes}, {"left_columns", t.left_columns},
       {"label_columns", t.row_label_columns()}};
}

void from_json(const nlohmann::json& j, Table& t) {
  using nlohmann::json;
  if (!j.is_object()) throw Error(": not an object");
  t.title = json_string(j, "", "title");
  t.header = json_strings(json_field(j, "", "header", json::value_t::array), "/header");
  const json& rows = json_field(j, "", "rows", json::value_t::array);
  t.rows.clear();
  for (std::size_t r = 0; r < rows.size(); ++r) {
    std::string pointer = "/rows/" + std::to_string(r);
    if (!rows[r].is_array()) throw Error(pointer + ": not an array");
    t.rows.push_back(json_strings(rows[r], pointer));
  }
  t.notes = json_strings(json_field(j, "", "notes", json::value_t::array), "/notes");
  auto column_count = [&](const char* key) {
    int n = json_field(j, "", key, json::value_t::number_unsigned).get<int>();
    if (n < 0 || n > int(t.header.size()))
      // Appended, not "/" + key: GCC 12 reports a false -Wstringop-overflow on that operator+.
      throw Error(std::string("/").append(key).append(": ") + std::to_string(n) +
                  " is not between 0 and the header's " + std::to_string(t.header.size()) + " columns");
    return n;
  };
  t.left_columns = column_count("left_columns");
  t.label_columns = j.contains("label_columns") ? column_count("label_columns") : -1;
}

} // namespace masq
