// What the MQTT feed publishes (docs/northbound.md, "MQTT"): topic names and JSON payloads built from a
// sensor's status copy. Pure: text from a SensorStatus.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include "gateway/gateway_status.h"
#include "monitoring/burst_feed.h"

namespace tiltgate {

// <prefix>/<sensor>/state, <prefix>/<sensor>/info, <prefix>/status and <prefix>/events.
std::string mqtt_state_topic(std::string_view prefix, std::string_view sensor);
std::string mqtt_info_topic(std::string_view prefix, std::string_view sensor);
std::string mqtt_status_topic(std::string_view prefix);
std::string mqtt_events_topic(std::string_view prefix);
std::string mqtt_burst_topic(std::string_view prefix, std::string_view sensor);

// The gateway's retained status: "online" while connected, "offline" as the last will and on
// a clean shutdown.
inline constexpr std::string_view kMqttOnline = "online";
inline constexpr std::string_view kMqttOffline = "offline";

// {"ts":..,"x":..,"y":..,"tilt":..,"online":..,"stale":..,"age_ms":..,"alarms":..,
// "wrong_device":..,"clock_synchronised":..,"clock_error_ms":..}. `ts` is the Unix time in
// milliseconds of the reading x and y come from (`now_unix_ms` less its age), or `now_unix_ms`
// when there is none yet (x, y and tilt are then null). The clock fields are the gateway's
// clock when the message was made (clock/clock_state.h): whether `ts` can be trusted, and
// within how many ms (null while unsynchronised).
std::string mqtt_state_json(const SensorStatus& sensor, const ClockState& clock,
                            std::int64_t now_unix_ms);

// A state kept in the backlog, as it is replayed: `state_json` with "historical":true added, so a
// subscriber that shows the latest state can tell a replayed, older one from a live one.
std::string mqtt_historical_state_json(std::string_view state_json);

// A batch of a burst's samples (monitoring/burst_feed.h), historical data by nature:
// {"sensor","burst","phase","historical":true,"samples":[{"ts","x","y","tilt","relative_x",
// "relative_y","displacement_mm","temperature","alarms","clock_synchronised"}]}, each sample
// with its reading's own time and null for a value the sensor has not.
std::string mqtt_burst_json(const monitoring::BurstBatch& batch);

// The sensor's identity: name, bus, unit_id, address, model, serial, firmware. Retained, and
// published again whenever it changes (the serial arrives after the first poll).
std::string mqtt_info_json(const SensorStatus& sensor);

}  // namespace tiltgate
