#include "console/settings_endpoint.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <nlohmann/json.hpp>

#include "console/console_audit.h"
#include "console/console_reply.h"
#include "console/request_guard.h"
#include "driver/closest_name.h"
#include "gateway/gateway.h"
#include "settings/sensor_settings.h"
#include "settings/setting_actions.h"
#include "settings/setting_writer.h"

namespace tiltgate {

using json = nlohmann::json;

namespace {

std::string number_text(double value) { return fmt::format("{}", value); }

const char* role_text(SettingRole role) {
  return role == SettingRole::operator_ ? "operator" : "admin";
}

// A command's values as buttons: what each does, the question before it, who may press it.
json actions_json(const std::vector<SettingAction>& actions) {
  json list = json::array();
  for (const SettingAction& action : actions)
    list.push_back({{"value", action.value},
                    {"name", action.name},
                    {"confirm", action.confirm},
                    {"role", role_text(action.role)}});
  return list;
}

}  // namespace

std::shared_ptr<GatewaySensor> SettingsEndpoint::find(const std::string& name) const {
  for (const auto& sensor : gateway_->sensors())
    if (sensor->config.name == name) return sensor;
  return nullptr;
}

HttpReply SettingsEndpoint::list(const std::string& name) const {
  const std::shared_ptr<GatewaySensor> sensor = find(name);
  if (!sensor) return error_reply(404, "no such sensor");
  const auto snapshot = sensor->snapshot();
  const std::vector<SensorSetting> list =
      sensor_settings(sensor->map, families_, snapshot ? &snapshot->state : nullptr);
  const std::vector<DeviceValue>& device_values = sensor->config.family_options.device_values();
  json settings = json::array();
  for (const SensorSetting& setting : list) {
    const SettingWords words =
        setting_words(setting, sensor->model, device_values, sensor->config.name);
    settings.push_back({{"name", setting.name},
                        {"label", words.label},
                        {"role", role_text(setting.role)},
                        {"operator_values", setting.operator_values},
                        {"actions", actions_json(words.actions)},
                        {"min", setting.min},
                        {"max", setting.max},
                        {"units", setting.units},
                        {"description", setting.description},
                        {"value", setting.value ? json(*setting.value) : json(nullptr)},
                        {"read_back", words.read_back}});
  }
  return json_reply(200, json{{"sensor", sensor->config.name}, {"settings", settings}});
}

boost::asio::awaitable<HttpReply> SettingsEndpoint::change(std::string name, SettingRequest asked,
                                                           std::string user, Role role) const {
  // Held to the end: a reload may drop the sensor while the write waits for its bus.
  const std::shared_ptr<GatewaySensor> sensor = find(name);
  if (!sensor) co_return error_reply(404, "no such sensor");
  const std::string full_name =
      (sensor->bus ? sensor->bus->name() + "/" : std::string()) + sensor->config.name;
  const std::vector<SensorSetting> list = sensor_settings(sensor->map, families_);
  const auto setting = std::find_if(list.begin(), list.end(), [&](const SensorSetting& s) {
    return s.name == asked.setting;
  });
  // A refused attempt is one record too, with the reason the reply gives.
  const auto refuse = [&](const std::string& why) {
    record_console_change(audit_, user, full_name, asked.setting, "", number_text(asked.value),
                          "refused: " + why);
    return error_reply(400, why);
  };
  if (setting == list.end()) {
    std::vector<std::string> names;
    for (const SensorSetting& s : list) names.push_back(s.name);
    const std::string guess = closest_name(asked.setting, names);
    co_return refuse(fmt::format("{} is not a setting of {}'s map; {}", asked.setting,
                                 sensor->config.name,
                                 !guess.empty()   ? fmt::format("did you mean {}?", guess)
                                 : names.empty() ? std::string("its map names none")
                                                 : fmt::format("its settings are {}",
                                                               fmt::join(names, ", "))));
  }
  if (!(asked.value >= setting->min && asked.value <= setting->max))
    co_return refuse(fmt::format("{} = {} is outside its range, {} to {}{}", asked.setting,
                                 number_text(asked.value), number_text(setting->min),
                                 number_text(setting->max),
                                 setting->units.empty() ? "" : " " + setting->units));
  const Role needed = role_to_write(*setting, asked.value) == SettingRole::operator_
                          ? Role::operator_
                          : Role::admin;
  if (!role_allows(role, needed)) {
    record_console_change(audit_, user, full_name, asked.setting, "", number_text(asked.value),
                          fmt::format("refused: the {} role may not change it", role_name(role)));
    // Said with the value when an operator may write others (a command whose 1 and 2 zero).
    const std::string what =
        setting->operator_values.empty()
            ? asked.setting
            : fmt::format("{} = {} (an operator may write {})", asked.setting,
                          number_text(asked.value), fmt::join(setting->operator_values, ", "));
    co_return error_reply(403, fmt::format("{} needs the {} role", what, role_name(needed)));
  }
  const SettingWriter writer(*gateway_, families_);
  // Named, not a temporary in the co_await: g++ 12 destroys such a temporary twice.
  WriteOrigin origin{"console", user};
  const SettingOutcome outcome =
      co_await writer.write(sensor->config.name, asked.setting, asked.value, std::move(origin));
  json body{{"sensor", sensor->config.name},
            {"setting", asked.setting},
            {"value", asked.value},
            {"old", outcome.old_value ? json(*outcome.old_value) : json(nullptr)}};
  switch (outcome.result) {
    case SettingOutcome::Result::ack:
      body["result"] = "ack";
      co_return json_reply(200, body);
    case SettingOutcome::Result::nak:
      body["result"] = audit_result(outcome);
      body["error"] = fmt::format("{} refused it: {}", sensor->config.name, outcome.detail);
      co_return json_reply(409, body);
    case SettingOutcome::Result::timeout:
      body["result"] = "timeout";
      body["error"] = fmt::format("{} did not answer: {}", sensor->config.name, outcome.detail);
      co_return json_reply(504, body);
    case SettingOutcome::Result::refused:
      break;
  }
  body["result"] = "refused: " + outcome.detail;
  body["error"] = outcome.detail;
  co_return json_reply(400, body);
}

}  // namespace tiltgate
