#include "commission_wire/json_fields.h"

#include <fmt/format.h>

#include "driver/hex.h"

namespace tiltgate {

using json = nlohmann::json;

namespace {

// "an object", "a string": what a value is, for the messages.
std::string json_value_kind(const json& value) {
  if (value.is_number_integer()) return "an integer";
  if (value.is_number_float()) return "a number with a fraction";
  const std::string name = value.type_name();  // "null", "object", "array", "string", "boolean"
  if (name == "null") return "null";
  return (name == "object" || name == "array" ? "an " : "a ") + name;
}

}  // namespace

JsonObjectReader::JsonObjectReader(const json& object, std::string path)
    : object_(object), path_(std::move(path)) {
  if (!object_.is_object())
    throw JsonFieldError(path_.empty()
                             ? fmt::format("expected a JSON object, got {}", json_value_kind(object_))
                             : fmt::format("field \"{}\": expected an object, got {}", path_,
                                           json_value_kind(object_)));
}

std::string JsonObjectReader::path_of(std::string_view key) const {
  return path_.empty() ? std::string(key) : fmt::format("{}.{}", path_, key);
}

std::string JsonObjectReader::item_name(std::string_view key, std::size_t index) {
  return fmt::format("{}[{}]", key, index);
}

void JsonObjectReader::fail(std::string_view key, std::string_view expected,
                            const json& value) const {
  throw JsonFieldError(
      fmt::format("field \"{}\": expected {}, got {}", path_of(key), expected, json_value_kind(value)));
}

std::string JsonObjectReader::integer_expectation(std::intmax_t min, std::uintmax_t max) {
  return fmt::format("an integer from {} to {}", min, max);
}

bool JsonObjectReader::has(std::string_view key) const { return object_.contains(key); }

const json& JsonObjectReader::field(std::string_view key) const {
  const auto found = object_.find(key);
  if (found == object_.end())
    throw JsonFieldError(fmt::format("field \"{}\" is missing", path_of(key)));
  return *found;
}

const json& JsonObjectReader::array_field(std::string_view key) const {
  const json& value = field(key);
  if (!value.is_array()) fail(key, "an array", value);
  return value;
}

bool JsonObjectReader::boolean(std::string_view key) const {
  const json& value = field(key);
  if (!value.is_boolean()) fail(key, "true or false", value);
  return value.get<bool>();
}

std::string JsonObjectReader::string(std::string_view key) const {
  const json& value = field(key);
  if (!value.is_string()) fail(key, "a string", value);
  return value.get<std::string>();
}

double JsonObjectReader::number(std::string_view key) const {
  const json& value = field(key);
  if (!value.is_number()) fail(key, "a number", value);
  return value.get<double>();
}

std::optional<double> JsonObjectReader::optional_number(std::string_view key) const {
  const json& value = field(key);
  if (value.is_null()) return std::nullopt;
  if (!value.is_number()) fail(key, "a number or null", value);
  return value.get<double>();
}

std::vector<std::uint8_t> JsonObjectReader::hex_bytes(std::string_view key) const {
  const json& value = field(key);
  if (!value.is_string()) fail(key, "hex bytes as a string", value);
  auto bytes = parse_hex_bytes(value.get_ref<const std::string&>());
  if (!bytes)
    throw JsonFieldError(fmt::format("field \"{}\": expected hex bytes (\"01 03 0A\"), got \"{}\"",
                                     path_of(key), value.get_ref<const std::string&>()));
  return std::move(*bytes);
}

JsonObjectReader JsonObjectReader::object(std::string_view key) const {
  return JsonObjectReader(field(key), path_of(key));
}

std::vector<std::string> JsonObjectReader::string_list(std::string_view key) const {
  std::vector<std::string> list;
  const json& array = array_field(key);
  for (std::size_t i = 0; i < array.size(); ++i) {
    if (!array[i].is_string()) fail(item_name(key, i), "a string", array[i]);
    list.push_back(array[i].get<std::string>());
  }
  return list;
}

}  // namespace tiltgate
