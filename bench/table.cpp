#include "bench/table.h"
#include <algorithm>

namespace masq {

namespace {
std::string cell(const std::vector<std::string>& row, std::size_t i) { return i < row.size() ? row[i] : std::string(); }
} // namespace

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

} // namespace masq
