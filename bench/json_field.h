// Checked reads of JSON fields for the files bench writes and `masq report` reads back
// (results.json and the tables in it): a field that is missing or of another type is one
// masq::Error naming it by its JSON pointer ("/run/quick: not true or false (string)"),
// relative to where the caller began; the caller prefixes the file.
#pragma once
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace masq {

// parent[key], of `type` (number_unsigned stands for any integer); `pointer` is parent's.
const nlohmann::json& json_field(const nlohmann::json& parent, const std::string& pointer, const std::string& key,
                                 nlohmann::json::value_t type);
std::string json_string(const nlohmann::json& parent, const std::string& pointer, const std::string& key);
// A list of strings at `pointer`.
std::vector<std::string> json_strings(const nlohmann::json& list, const std::string& pointer);

} // namespace masq
