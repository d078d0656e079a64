/// @file masq/names.h
/// Option tables: one per option, each row a value, the name that options, files and
/// reports use for it, and one line saying what it does. Parsing, printing, the command
/// line's choices and its help text all read the same rows, so a new value is one new row.
#pragma once
#include "masq/error.h"
#include <cstddef>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

namespace masq {

/// The row of a plain option table. Tables whose rows say more (builder_table, the
/// backend registry) use their own row type: it needs `name` and `help`, and `value`
/// for the functions that map names to values.
template <class E>
struct NameRow {
  E value;
  const char* name;
  const char* help; ///< one line, no trailing period
};

/// "a", "a or b", "a, b or c": how messages and help text list choices.
inline std::string choice_list(std::span<const std::string> items) {
  std::string out;
  for (std::size_t i = 0; i < items.size(); ++i) {
    if (i > 0) out += i + 1 == items.size() ? " or " : ", ";
    out += items[i];
  }
  return out;
}

/// Keeps every row (the default filter of NameTable's lists).
struct EveryRow {
  template <class Row>
  constexpr bool operator()(const Row&) const {
    return true;
  }
};

/// An option table: what the option is called in messages ("method") and its rows, in
/// the order lists and help show them.
template <class Row>
class NameTable {
 public:
  constexpr NameTable(const char* what, std::span<const Row> rows) : what_(what), rows_(rows) {}

  constexpr const char* what() const { return what_; }
  constexpr std::span<const Row> rows() const { return rows_; }
  constexpr std::size_t size() const { return rows_.size(); }

  /// The row named `name`, or nullptr. A row with an `alias` member (an older name users
  /// still type, nullptr for none) is found by that name too; lists and output show `name`.
  constexpr const Row* find(std::string_view name) const {
    for (const Row& r : rows_) {
      if (name == r.name) return &r;
      if constexpr (requires { r.alias; })
        if (r.alias != nullptr && name == r.alias) return &r;
    }
    return nullptr;
  }
  /// The row named `name`; throws masq::Error "unknown <what> '<name>' (expected a, b or c)".
  const Row& at(std::string_view name) const {
    if (const Row* r = find(name)) return *r;
    throw Error("unknown " + std::string(what_) + " '" + std::string(name) + "' (expected " + choices() + ")");
  }
  /// The value named `name` (throws as at()).
  auto parse(std::string_view name) const { return at(name).value; }

  /// The row of `value`; throws masq::Error for a value no row holds.
  template <class V>
  const Row& row(V value) const {
    for (const Row& r : rows_)
      if (r.value == value) return r;
    if constexpr (std::is_enum_v<V>)
      throw Error("no " + std::string(what_) + " " + std::to_string(static_cast<long long>(value)));
    else
      throw Error("no " + std::string(what_) + " of that value");
  }
  template <class V>
  const char* name(V value) const {
    return row(value).name;
  }
  /// Every value, in table order.
  auto values() const {
    std::vector<decltype(rows_.front().value)> out;
    for (const Row& r : rows_) out.push_back(r.value);
    return out;
  }

  /// The names of the rows `keep` accepts (CLI11's IsMember takes them as they are).
  template <class Keep = EveryRow>
  std::vector<std::string> names(Keep keep = {}) const {
    std::vector<std::string> out;
    for (const Row& r : rows_)
      if (keep(r)) out.emplace_back(r.name);
    return out;
  }
  /// names() and every row's alias: what a command line accepts (its help shows names()).
  template <class Keep = EveryRow>
  std::vector<std::string> accepted_names(Keep keep = {}) const {
    std::vector<std::string> out = names(keep);
    for (const Row& r : rows_)
      if constexpr (requires { r.alias; })
        if (r.alias != nullptr && keep(r)) out.emplace_back(r.alias);
    return out;
  }
  /// "a, b or c".
  template <class Keep = EveryRow>
  std::string choices(Keep keep = {}) const {
    return choice_list(names(keep));
  }
  /// "a (what a does), b (what b does) or c (what c does)": the values part of a help text.
  template <class Keep = EveryRow>
  std::string help(Keep keep = {}) const {
    std::vector<std::string> items;
    for (const Row& r : rows_)
      if (keep(r)) items.push_back(*r.help ? std::string(r.name) + " (" + r.help + ")" : std::string(r.name));
    return choice_list(items);
  }

 private:
  const char* what_;
  std::span<const Row> rows_;
};

template <class Row, std::size_t N>
NameTable(const char*, const Row (&)[N]) -> NameTable<Row>;

} // namespace masq
