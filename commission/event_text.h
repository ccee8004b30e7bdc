// The engine's results as the text a person reads (commission/commission_events.h): what
// `tiltgate scan`, `raw`, `info` and `set` print, and what the web console shows as their
// output. Pure.
#pragma once

#include <string>

#include "commission/commission_events.h"

namespace tiltgate {

// The table of what answered, the notes on sensors found at several rates, and the summary:
// one line each, every line ending in a newline.
std::string scan_result_text(const ScanFinishedEvent& finished);

// "sent:     ..." and "received: ..." and, when answered, the reply decoded: one line each.
std::string exchange_text(const ExchangeEvent& exchange);

// What the checksum said of the reply: its verdict, or "nothing" (with why bytes that came
// were not one).
std::string received_verdict(const ExchangeEvent& exchange);

// A sensor as `info` shows it: its identity and angles after a reading, its address and status
// without one, or what a device without its driver said of itself. One line each.
std::string sensor_reading_text(const SensorReadingEvent& reading);

// A setting's value as `set` shows it: "5", "0.25".
std::string setting_value_text(double value);

// `set`'s lines: every write acknowledged, the move, the restart, the configuration file
// following it, the values read back. One line each, every line ending in a newline.
std::string setting_applied_text(const SettingAppliedEvent& applied);
std::string address_moved_text(const AddressMovedEvent& moved);
std::string sensor_restarted_text(const SensorRestartedEvent& restarted);
std::string config_updated_text(const ConfigUpdatedEvent& updated);
std::string settings_read_text(const SettingsReadEvent& read);

}  // namespace tiltgate
