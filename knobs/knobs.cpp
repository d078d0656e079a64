// The one reader of the environment (include/masq/knobs.h): every knob is parsed and
// checked here, so each has one meaning and one error wherever it is read.
#include "masq/knobs.h"
#include "masq/error.h"
#include <cstdlib>
#include <vector>

namespace masq {

namespace {

const char* raw(const char* name) { return std::getenv(name); }

std::vector<std::string_view> split_choices(const char* choices) {
  std::vector<std::string_view> out;
  std::string_view rest = choices;
  for (;;) {
    const std::size_t bar = rest.find('|');
    out.push_back(rest.substr(0, bar));
    if (bar == std::string_view::npos) return out;
    rest.remove_prefix(bar + 1);
  }
}

[[noreturn]] void bad_value(const KnobRow& row, std::string_view owner, std::string_view value) {
  std::string msg = owner.empty() ? std::string() : std::string(owner) + ": ";
  msg += std::string(row.name) + "='" + std::string(value) + "' is not " + knob_expected(row);
  throw Error(msg);
}

// Decimal digits only: no sign, no spaces, no suffix, so that "12kB" or " 8" is an
// error rather than a number strtoull would half read.
std::optional<std::uint64_t> parse_decimal(std::string_view text) {
  if (text.empty()) return std::nullopt;
  std::uint64_t n = 0;
  for (char c : text) {
    if (c < '0' || c > '9') return std::nullopt;
    const std::uint64_t digit = static_cast<std::uint64_t>(c - '0');
    if (n > (kNoKnobMax - digit) / 10) return std::nullopt;
    n = n * 10 + digit;
  }
  return n;
}

void expect_type(const KnobRow& row, bool ok, const char* accessor) {
  if (!ok) throw Error(std::string(accessor) + "(" + row.name + "): the knob's row has another type");
}

} // namespace

std::optional<std::string> knob_text(Knob k) {
  const char* v = raw(knob_name(k));
  if (v == nullptr) return std::nullopt;
  return std::string(v);
}

std::optional<std::uint64_t> knob_integer(Knob k, std::string_view owner) {
  const KnobRow& row = knob_row(k);
  expect_type(row, row.type == KnobType::Integer, "knob_integer");
  const char* v = raw(row.name);
  if (v == nullptr || *v == '\0') return std::nullopt;
  const std::optional<std::uint64_t> n = parse_decimal(v);
  if (!n || *n < row.min || *n > row.max) bad_value(row, owner, v);
  return n;
}

std::string_view knob_choice(Knob k, std::string_view owner) {
  const KnobRow& row = knob_row(k);
  expect_type(row, row.type == KnobType::Choice || row.type == KnobType::Flag, "knob_choice");
  const char* v = raw(row.name);
  const std::string_view value = v == nullptr || *v == '\0' ? std::string_view(row.default_text) : v;
  for (std::string_view choice : split_choices(row.choices))
    if (choice == value) return choice;
  bad_value(row, owner, value);
}

bool knob_flag(Knob k, std::string_view owner) {
  expect_type(knob_row(k), knob_row(k).type == KnobType::Flag, "knob_flag");
  return knob_choice(k, owner) == "1";
}

std::string knob_expected(const KnobRow& row) {
  switch (row.type) {
    case KnobType::Integer:
      if (row.min == 1 && row.max == kNoKnobMax) return "a positive integer";
      return "an integer from " + std::to_string(row.min) + " to " + std::to_string(row.max);
    case KnobType::Choice:
    case KnobType::Flag: {
      const std::vector<std::string_view> choices = split_choices(row.choices);
      std::string out;
      for (std::size_t i = 0; i < choices.size(); ++i) {
        if (i > 0) out += i + 1 == choices.size() ? " or " : ", ";
        // Appended piece by piece: GCC 12 warns (-Wrestrict, a false positive) of "'" + s.
        out += '\'';
        out += choices[i];
        out += '\'';
      }
      return out;
    }
    case KnobType::Path: return "a path";
    case KnobType::List: return "a comma-separated list of names";
    case KnobType::Device: return "a device index or a name substring";
  }
  return "valid";
}

std::string knob_problem(Knob k) {
  try {
    switch (knob_row(k).type) {
      case KnobType::Integer: knob_integer(k); break;
      case KnobType::Choice:
      case KnobType::Flag: knob_choice(k); break;
      case KnobType::Path:
      case KnobType::List:
      case KnobType::Device: break;
    }
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

std::optional<std::string> system_env(const char* name) {
  const char* v = raw(name);
  if (v == nullptr) return std::nullopt;
  return std::string(v);
}

} // namespace masq
