#include "commission/set_config_update.h"

#include <filesystem>
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <fstream>

#include "config/config_edit.h"
#include "toml/text_file.h"

namespace tiltgate {

namespace {

// The new text beside the file, then renamed over it, so that a failure leaves the old file
// whole; the file keeps its permissions.
Expected<Done, std::string> replace_file(const std::string& path, const std::string& text) {
  const std::string temporary = path + ".tiltgate-set.tmp";
  {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    out << text;
    out.close();
    if (!out) return Unexpected{fmt::format("cannot write {}", temporary)};
  }
  std::error_code ec;
  std::filesystem::permissions(temporary, std::filesystem::status(path, ec).permissions(), ec);
  std::filesystem::rename(temporary, path, ec);
  if (ec) {
    std::filesystem::remove(temporary, ec);
    return Unexpected{fmt::format("cannot replace {}: {}", path, ec.message())};
  }
  return Done{};
}

}  // namespace

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
  if (auto written = replace_file(options.config, edited); !written)
    return Unexpected{fmt::format("{} not updated: {}", options.config, written.error())};
  return std::optional<std::string>{fmt::format("{}", fmt::join(changes, "\n"))};
}

}  // namespace tiltgate
