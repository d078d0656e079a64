#include "bench/json_field.h"
#include "masq/error.h"

namespace masq {

namespace {
using nlohmann::json;

bool has_type(const json& j, json::value_t type) {
  return type == json::value_t::number_unsigned ? j.is_number_integer() : j.type() == type;
}

const char* type_name(json::value_t type) {
  switch (type) {
    case json::value_t::object: return "an object";
    case json::value_t::array: return "an array";
    case json::value_t::string: return "a string";
    case json::value_t::boolean: return "true or false";
    default: return "an integer";
  }
}
} // namespace

const json& json_field(const json& parent, const std::string& pointer, const std::string& key, json::value_t type) {
  const std::string at = pointer + "/" + key;
  if (!parent.is_object()) throw Error(pointer + ": not an object (" + parent.type_name() + ")");
  auto it = parent.find(key);
  if (it == parent.end()) throw Error(at + ": missing");
  if (!has_type(*it, type)) throw Error(at + ": not " + type_name(type) + " (" + it->type_name() + ")");
  return *it;
}

std::string json_string(const json& parent, const std::string& pointer, const std::string& key) {
  return json_field(parent, pointer, key, json::value_t::string).get<std::string>();
}

std::vector<std::string> json_strings(const json& list, const std::string& pointer) {
  if (!list.is_array()) throw Error(pointer + ": not an array (" + list.type_name() + ")");
  std::vector<std::string> out;
  for (std::size_t i = 0; i < list.size(); ++i) {
    if (!list[i].is_string()) throw Error(pointer + "/" + std::to_string(i) + ": not a string");
    out.push_back(list[i].get<std::string>());
  }
  return out;
}

} // namespace masq
