#include "commission/set_config_update.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "config/config_edit.h"
#include "store/whole_file_write.h"
#include "toml/text_file.h"

namespace tiltgate {

Expected<std::optional<std::string>, std::string> update_config_file(const BusOptions& options,
                                                                      const SensorConfig& sensor,
                                                                      std::uint32_t old_address,
                                                                      const SetPlan& plan) {
  if (options.config.empty() || !options.port.empty()) return std::optional<std::string>{};
  if (!plan.new_address && !plan.new_baud) return std::optional<std::string>{};
  const auto text = toml_input::read_text_file(options.config);
  if (!text) return Unexpected{fmt::format("{} not updated: {}", options.config, text.error())};
  std::string edited = *text;
  std::vector<std::string> changes;
  if (plan.new_address) {
    auto edit = edit_sensor_address(edited, sensor.name, *plan.new_address);
    if (!edit) return Unexpected{fmt::format("{} not updated: {}", options.config, edit.error())};
    edited = std::move(edit->text);
    changes.push_back(fmt::format("updated {}: sensor {} address {} -> {}", options.config,
                                  sensor.name, old_address, *plan.new_address));
  }
  if (plan.new_baud) {
    auto edit = edit_bus_baud(edited, sensor.bus, *plan.new_baud);
    if (!edit) return Unexpected{fmt::format("{} not updated: {}", options.config, edit.error())};
    edited = std::move(edit->text);
    changes.push_back(fmt::format("updated {}: bus {} baud {} -> {}", options.config, sensor.bus,
                                  edit->old_value.empty() ? "(not given)" : edit->old_value,
                                  *plan.new_baud));
  }
  // Replaced whole, keeping its owner, group and mode: root's `set` leaves the service's file
  // the service's (the console may replace it next).
  if (auto written = write_whole_file(options.config, edited, 0640, FileMode::keep_old); !written)
    return Unexpected{fmt::format("{} not updated: {}", options.config, written.error())};
  return std::optional<std::string>{fmt::format("{}", fmt::join(changes, "\n"))};
}

}  // namespace tiltgate
