#include "commission/event_text.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "commission/reading_format.h"
#include "driver/hex.h"

namespace tiltgate {

std::string scan_result_text(const ScanFinishedEvent& finished) {
  std::string text;
  if (!finished.found.empty()) {
    text += scan_header() + "\n";
    for (const FoundSensor& s : finished.found) text += scan_row(s) + "\n";
  }
  for (const RepeatedSensor& r : finished.repeated) text += repeated_note(r) + "\n";
  text += scan_summary(finished.found, finished.probes, finished.took) + "\n";
  return text;
}

std::string received_verdict(const ExchangeEvent& exchange) {
  if (exchange.answered) return exchange.verdict;
  return exchange.rejected_verdict.empty() ? "nothing"
                                           : "nothing valid (" + exchange.rejected_verdict + ")";
}

std::string exchange_text(const ExchangeEvent& exchange) {
  std::string text = "sent:     " + hex_bytes(exchange.sent);
  if (exchange.address_bytes > 0)
    text += fmt::format("  (the first {} with the 9th bit set)",
                        exchange.address_bytes == 1
                            ? std::string("byte")
                            : fmt::format("{} bytes", exchange.address_bytes));
  text += "\n";
  if (!exchange.answered) return text + "received: " + received_verdict(exchange) + "\n";
  text += fmt::format("received: {}  ({})\n", hex_bytes(exchange.received), exchange.verdict);
  return text + exchange.decoded + "\n";
}

std::string sensor_reading_text(const SensorReadingEvent& reading) {
  const std::string address = fmt::format("address:    {}\n", reading.address);
  if (reading.model.empty())
    return address + reading.self_report +
           (reading.result == PollResult::silent ? "status:     no reply\n" : "");
  if (reading.result != PollResult::reading)
    return address + fmt::format("status:     {}\n", reading.status);
  return sensor_info_text(reading);
}

std::string setting_value_text(double value) { return fmt::format("{}", value); }

std::string setting_applied_text(const SettingAppliedEvent& applied) {
  return fmt::format("{}{} at address {}: acknowledged\n", applied.setting,
                     applied.permanent ? " --permanent" : "", applied.address);
}

std::string address_moved_text(const AddressMovedEvent& moved) {
  std::string text;
  if (!moved.gateway_sensor.empty())
    text += fmt::format("gateway: sensor {} is polled at address {} from now on\n",
                        moved.gateway_sensor, moved.to);
  return text + fmt::format("the sensor now answers at address {}\n", moved.to);
}

std::string sensor_restarted_text(const SensorRestartedEvent& restarted) {
  if (!restarted.baud) return "the sensor restarted\n";
  if (restarted.line_follows)
    return fmt::format("the sensor restarted at {} baud; the line follows it\n", *restarted.baud);
  // The gateway's bus keeps its rate: the sensor has left it until the bus is moved too.
  return fmt::format("the sensor restarted at {} baud; the gateway's bus stays at {} baud, so it "
                     "no longer answers there: set the others, then the bus's baud in the "
                     "configuration\n",
                     *restarted.baud, restarted.bus_baud);
}

std::string config_updated_text(const ConfigUpdatedEvent& updated) {
  return fmt::format("{}\n", fmt::join(updated.changes, "\n"));
}

std::string settings_read_text(const SettingsReadEvent& read) {
  std::string text;
  for (const SettingValue& setting : read.settings)
    text += fmt::format("{:<11} {}\n", setting.name + ":",
                        setting.value ? setting_value_text(*setting.value) : "-");
  return text;
}

}  // namespace tiltgate
