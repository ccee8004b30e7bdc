#include "settings/setting_actions.h"

#include <algorithm>

namespace tiltgate {

namespace {

constexpr std::string_view kSensorPlaceholder = "{sensor}";

const SettingDescriptor* descriptor_of(const ModelDescriptor* model, WriteTarget target) {
  if (model == nullptr) return nullptr;
  const auto found = std::find_if(model->settings.begin(), model->settings.end(),
                                  [&](const SettingDescriptor& s) { return s.id == target; });
  return found == model->settings.end() ? nullptr : &*found;
}

}  // namespace

std::string naming_sensor(std::string_view text, std::string_view sensor) {
  std::string out;
  for (std::size_t at = 0;;) {
    const std::size_t found = text.find(kSensorPlaceholder, at);
    out += text.substr(at, found - at);
    if (found == std::string_view::npos) return out;
    out += sensor;
    at = found + kSensorPlaceholder.size();
  }
}

SettingWords setting_words(const SensorSetting& setting, const ModelDescriptor* model,
                           std::span<const DeviceValue> device_values, std::string_view sensor) {
  SettingWords words{setting.name, {}, false};
  const WriteTarget target = *setting.point->write;
  if (target.is_device_value()) {
    // A profile's value is read with every poll (setting_value()).
    words.read_back = true;
    if (target.device_index() < device_values.size() &&
        !device_values[target.device_index()].label.empty())
      words.label = device_values[target.device_index()].label;
    return words;
  }
  const SettingDescriptor* descriptor = descriptor_of(model, target);
  if (descriptor == nullptr) return words;
  if (!descriptor->label.empty()) words.label = descriptor->label;
  words.read_back = descriptor->read_back;
  for (const CommandAction& action : descriptor->actions)
    words.actions.push_back({action.value, std::string(action.name),
                             naming_sensor(action.confirm, sensor),
                             role_to_write(setting, action.value)});
  return words;
}

}  // namespace tiltgate
