#include "console/console_requests.h"

#include <fmt/format.h>

#include <cmath>
#include <tuple>
#include <nlohmann/json.hpp>

namespace tiltgate {

namespace {

using json = nlohmann::json;

Expected<json, std::string> object_of(std::string_view body) {
  json parsed = json::parse(body, nullptr, false);
  if (parsed.is_discarded()) return Unexpected{std::string("the body is not JSON")};
  if (!parsed.is_object()) return Unexpected{std::string("the body is not a JSON object")};
  return parsed;
}

Expected<std::string, std::string> string_field(const json& object, const char* name,
                                                std::size_t max, bool required = true) {
  const auto found = object.find(name);
  if (found == object.end()) {
    if (!required) return std::string();
    return Unexpected{fmt::format("\"{}\" is missing", name)};
  }
  if (!found->is_string()) return Unexpected{fmt::format("\"{}\" is not a string", name)};
  std::string value = found->get<std::string>();
  if (value.size() > max)
    return Unexpected{fmt::format("\"{}\" is longer than {} bytes", name, max)};
  return value;
}

Expected<std::int64_t, std::string> integer_field(const json& object, const char* name,
                                                  std::int64_t fallback, bool required) {
  const auto found = object.find(name);
  if (found == object.end()) {
    if (!required) return fallback;
    return Unexpected{fmt::format("\"{}\" is missing", name)};
  }
  if (!found->is_number_integer())
    return Unexpected{fmt::format("\"{}\" is not a whole number", name)};
  return found->get<std::int64_t>();
}

}  // namespace

Expected<LoginRequest, std::string> parse_login_request(std::string_view body) {
  auto object = object_of(body);
  if (!object) return Unexpected{object.error()};
  auto user = string_field(*object, "user", kMaxUserName);
  if (!user) return Unexpected{user.error()};
  auto password = string_field(*object, "password", kMaxPassword);
  if (!password) return Unexpected{password.error()};
  return LoginRequest{std::move(*user), std::move(*password)};
}

Expected<SettingRequest, std::string> parse_setting_request(std::string_view body) {
  auto object = object_of(body);
  if (!object) return Unexpected{object.error()};
  auto setting = string_field(*object, "setting", 64);
  if (!setting) return Unexpected{setting.error()};
  const auto value = object->find("value");
  if (value == object->end()) return Unexpected{std::string("\"value\" is missing")};
  double number = 0;
  if (value->is_number())
    number = value->get<double>();
  else if (value->is_boolean())
    number = value->get<bool>() ? 1 : 0;
  else
    return Unexpected{std::string("\"value\" is not a number")};
  if (!std::isfinite(number)) return Unexpected{std::string("\"value\" is not a finite number")};
  return SettingRequest{std::move(*setting), number};
}

Expected<ConfigText, std::string> parse_config_text(std::string_view body) {
  auto object = object_of(body);
  if (!object) return Unexpected{object.error()};
  auto text = string_field(*object, "text", 1 << 20);
  if (!text) return Unexpected{text.error()};
  auto confirm = integer_field(*object, "confirm_s", ConfigText::kDefaultConfirmSeconds, false);
  if (!confirm) return Unexpected{confirm.error()};
  if (*confirm < ConfigText::kMinConfirmSeconds || *confirm > ConfigText::kMaxConfirmSeconds)
    return Unexpected{fmt::format("\"confirm_s\" is {}, expected {} to {} seconds", *confirm,
                                  ConfigText::kMinConfirmSeconds, ConfigText::kMaxConfirmSeconds)};
  return ConfigText{std::move(*text), *confirm};
}

Expected<ScanRequest, std::string> parse_scan_request(std::string_view body) {
  if (body.empty()) return ScanRequest{};
  auto object = object_of(body);
  if (!object) return Unexpected{object.error()};
  auto from = integer_field(*object, "from", 1, false);
  if (!from) return Unexpected{from.error()};
  auto to = integer_field(*object, "to", 0, false);
  if (!to) return Unexpected{to.error()};
  if (*from < 0 || *from > 65535 || *to < 0 || *to > 65535)
    return Unexpected{std::string("\"from\" and \"to\" are bus addresses, 0 to 65535")};
  if (*to != 0 && *to < *from) return Unexpected{std::string("\"to\" is below \"from\"")};
  return ScanRequest{*from, *to};
}

Expected<RawRequest, std::string> parse_raw_request(std::string_view body) {
  auto object = object_of(body);
  if (!object) return Unexpected{object.error()};
  auto address = integer_field(*object, "address", 0, true);
  if (!address) return Unexpected{address.error()};
  auto function = integer_field(*object, "function", 0, true);
  if (!function) return Unexpected{function.error()};
  auto data = string_field(*object, "data", 1024, false);
  if (!data) return Unexpected{data.error()};
  if (*address < 0 || *address > 65535 || *function < 0 || *function > 65535)
    return Unexpected{std::string("\"address\" and \"function\" are 0 to 65535")};
  return RawRequest{*address, *function, std::move(*data)};
}

Expected<FormEditRequest, std::string> parse_form_edit_request(std::string_view body) {
  auto object = object_of(body);
  if (!object) return Unexpected{object.error()};
  FormEditRequest request;
  for (const auto& [name, field, max, required] :
       {std::tuple{"text", &request.text, std::size_t(1) << 20, true},
        std::tuple{"action", &request.action, std::size_t(16), true},
        std::tuple{"table", &request.table, std::size_t(16), true},
        std::tuple{"name", &request.name, std::size_t(256), false}}) {
    auto value = string_field(*object, name, max, required);
    if (!value) return Unexpected{value.error()};
    *field = std::move(*value);
  }
  if (request.action != "add" && request.action != "edit" && request.action != "remove")
    return Unexpected{std::string("\"action\" is not \"add\", \"edit\" or \"remove\"")};
  if (request.table != "bus" && request.table != "sensor")
    return Unexpected{std::string("\"table\" is not \"bus\" or \"sensor\"")};
  if (request.action != "add" && request.name.empty())
    return Unexpected{fmt::format("\"name\" is missing: which {} to {}", request.table,
                                  request.action)};
  const auto values = object->find("values");
  if (values != object->end()) {
    if (!values->is_object()) return Unexpected{std::string("\"values\" is not an object")};
    if (values->size() > 64) return Unexpected{std::string("\"values\" has more than 64 keys")};
    for (const auto& [key, value] : values->items()) {
      if (!value.is_string())
        return Unexpected{fmt::format("\"values\".\"{}\" is not a string", key.substr(0, 64))};
      if (key.size() > 64 || value.get_ref<const std::string&>().size() > 4096)
        return Unexpected{fmt::format("\"values\".\"{}\" is too long", key.substr(0, 64))};
      request.values[key] = value.get<std::string>();
    }
  }
  return request;
}

}  // namespace tiltgate
