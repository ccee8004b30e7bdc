#include "commission/set_config_update.h"

#include <fmt/format.h>

#include "config/config_edit.h"
#include "store/whole_file_write.h"
#include "toml/text_file.h"

namespace tiltgate {

std::string followed_config_file(const BusOptions& options) {
  return options.port.empty() ? options.config : std::string();
}

Expected<std::vector<std::string>, std::string> update_config_file(const std::string& config_file,
                                                                   const SensorConfig& sensor,
                                                                   std::uint32_t old_address,
                                                                   const SetPlan& plan) {
  if (config_file.empty()) return std::vector<std::string>{};
  if (!plan.new_address && !plan.new_baud) return std::vector<std::string>{};
  const auto text = toml_input::read_text_file(config_file);
  if (!text) return Unexpected{fmt::format("{} not updated: {}", config_file, text.error())};
  std::string edited = *text;
  std::vector<std::string> changes;
  if (plan.new_address) {
    auto edit = edit_sensor_address(edited, sensor.name, *plan.new_address);
    if (!edit) return Unexpected{fmt::format("{} not updated: {}", config_file, edit.error())};
    edited = std::move(edit->text);
    changes.push_back(fmt::format("updated {}: sensor {} address {} -> {}", config_file,
                                  sensor.name, old_address, *plan.new_address));
  }
  if (plan.new_baud) {
    auto edit = edit_bus_baud(edited, sensor.bus, *plan.new_baud);
    if (!edit) return Unexpected{fmt::format("{} not updated: {}", config_file, edit.error())};
    edited = std::move(edit->text);
    changes.push_back(fmt::format("updated {}: bus {} baud {} -> {}", config_file, sensor.bus,
                                  edit->old_value.empty() ? "(not given)" : edit->old_value,
                                  *plan.new_baud));
  }
  // Replaced whole, keeping its owner, group and mode: root's `set` leaves the service's file
  // the service's (the console may replace it next).
  if (auto written = write_whole_file(config_file, edited, 0640, FileMode::keep_old); !written)
    return Unexpected{fmt::format("{} not updated: {}", config_file, written.error())};
  return changes;
}

}  // namespace tiltgate
