// The fields of each of the engine's events as JSON, one overload pair an event, for
// commission_wire/event_json.cpp to dispatch on: `event_fields` writes the event's own fields (the
// caller adds its "event" name), `read_event_fields` reads them back, throwing JsonFieldError
// (commission_wire/json_fields.h) for a field that is missing or not what it should be. Internal to
// the JSON layer: others use commission_wire/event_json.h.
#pragma once

#include <nlohmann/json.hpp>

#include "commission/commission_events.h"
#include "commission_wire/json_fields.h"

namespace tiltgate {

// commission_wire/scan_event_json.cpp: a scan's progress, the devices it finds, its end.
nlohmann::json event_fields(const ProgressEvent& event);
nlohmann::json event_fields(const DeviceFoundEvent& event);
nlohmann::json event_fields(const ScanFinishedEvent& event);
void read_event_fields(const JsonObjectReader& fields, ProgressEvent& event);
void read_event_fields(const JsonObjectReader& fields, DeviceFoundEvent& event);
void read_event_fields(const JsonObjectReader& fields, ScanFinishedEvent& event);

// commission_wire/reading_event_json.cpp: a sensor's reading (info, watch, set) and watch's rounds.
nlohmann::json event_fields(const SensorReadingEvent& event);
nlohmann::json event_fields(const WatchRoundEvent& event);
void read_event_fields(const JsonObjectReader& fields, SensorReadingEvent& event);
void read_event_fields(const JsonObjectReader& fields, WatchRoundEvent& event);

// commission_wire/set_event_json.cpp: what `set` reports of its writes and what followed them.
nlohmann::json event_fields(const SettingAcknowledgedEvent& event);
nlohmann::json event_fields(const SettingAppliedEvent& event);
nlohmann::json event_fields(const AddressMovedEvent& event);
nlohmann::json event_fields(const SensorRestartedEvent& event);
nlohmann::json event_fields(const ConfigUpdatedEvent& event);
nlohmann::json event_fields(const SettingsReadEvent& event);
void read_event_fields(const JsonObjectReader& fields, SettingAcknowledgedEvent& event);
void read_event_fields(const JsonObjectReader& fields, SettingAppliedEvent& event);
void read_event_fields(const JsonObjectReader& fields, AddressMovedEvent& event);
void read_event_fields(const JsonObjectReader& fields, SensorRestartedEvent& event);
void read_event_fields(const JsonObjectReader& fields, ConfigUpdatedEvent& event);
void read_event_fields(const JsonObjectReader& fields, SettingsReadEvent& event);

// commission_wire/event_json.cpp itself: notes, failures, a gateway's warning and raw's exchange.
nlohmann::json event_fields(const NoteEvent& event);
nlohmann::json event_fields(const FailedEvent& event);
nlohmann::json event_fields(const GatewayWarningEvent& event);
nlohmann::json event_fields(const ExchangeEvent& event);
void read_event_fields(const JsonObjectReader& fields, NoteEvent& event);
void read_event_fields(const JsonObjectReader& fields, FailedEvent& event);
void read_event_fields(const JsonObjectReader& fields, GatewayWarningEvent& event);
void read_event_fields(const JsonObjectReader& fields, ExchangeEvent& event);

}  // namespace tiltgate
