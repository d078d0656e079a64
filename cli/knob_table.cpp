#include "cli/knob_table.h"
#include "masq/knobs.h"
#include <fmt/format.h>
#include <string_view>

namespace masq::cli {

namespace {

constexpr std::size_t kColumns = 100;
constexpr std::size_t kNameWidth = 30;
constexpr std::string_view kIndent = "    ";

// "positive integer", "integer 0..1000000", "on, off", "path".
std::string type_text(const KnobRow& row) {
  switch (row.type) {
    case KnobType::Integer:
      if (row.min == 1 && row.max == kNoKnobMax) return "positive integer";
      return fmt::format("integer {}..{}", row.min, row.max);
    case KnobType::Choice:
    case KnobType::Flag: {
      std::string out = row.type == KnobType::Flag ? "flag " : "";
      for (char c : std::string_view(row.choices)) out += c == '|' ? std::string(", ") : std::string(1, c);
      return out;
    }
    case KnobType::Path: return "path";
    case KnobType::List: return "comma-separated names";
    case KnobType::Device: return "device selector";
  }
  return "";
}

// `text` in lines of at most kColumns, each starting with kIndent, broken at spaces (a
// word longer than a line keeps its own line).
std::string wrapped(std::string_view text) {
  std::string out, line;
  std::size_t start = 0;
  while (start < text.size()) {
    std::size_t end = text.find(' ', start);
    if (end == std::string_view::npos) end = text.size();
    const std::string_view word = text.substr(start, end - start);
    if (!line.empty() && kIndent.size() + line.size() + 1 + word.size() > kColumns) {
      out += std::string(kIndent) + line + "\n";
      line.clear();
    }
    line += (line.empty() ? "" : " ") + std::string(word);
    start = end + 1;
  }
  if (!line.empty()) out += std::string(kIndent) + line + "\n";
  return out;
}

} // namespace

std::string knob_table_text() {
  std::string out = "Environment variables (include/masq/knobs.h; docs/knobs.md)\n";
  for (const KnobRow& row : knob_rows) {
    const std::optional<std::string> value = knob_text(row.knob);
    out += fmt::format("\n{:<{}}{}\n", row.name, kNameWidth, value ? "'" + *value + "'" : std::string("(unset)"));
    out += wrapped(fmt::format("[{}; default: {}] {}. Read by {}.", type_text(row), row.default_text, row.meaning,
                               row.readers));
    if (const std::string problem = knob_problem(row.knob); !problem.empty()) out += wrapped("bad: " + problem);
  }
  return out;
}

std::string knob_table_markdown() {
  std::string out =
      "# Knobs\n\n"
      "The environment variables masq reads. Generated from `knob_rows` (`include/masq/knobs.h`) by\n"
      "`masq info --env --markdown > docs/knobs.md`; ctest `knob_docs` fails when this page and the table\n"
      "differ. `masq info --env` lists the same rows with the values set now. Every reader goes\n"
      "through the accessors of `include/masq/knobs.h` (`knobs/knobs.cpp` alone reads the environment), so a\n"
      "value outside its type is one error naming the variable, its value and what is expected. Unset\n"
      "or empty is the default, except where a row says otherwise; knobs are read at each use unless\n"
      "the row says otherwise.\n\n"
      "| variable | type | default | meaning | read by |\n"
      "|---|---|---|---|---|\n";
  for (const KnobRow& row : knob_rows)
    out += fmt::format("| `{}` | {} | {} | {} | {} |\n", row.name, type_text(row), row.default_text, row.meaning,
                       row.readers);
  return out;
}

} // namespace masq::cli
