// Which event an object is, by its "event" name, and the events too small for a file of their
// own (a note, a failure, a gateway's warning, raw's exchange). The fields of the others:
// commission_wire/event_json_parts.h.
#include "commission_wire/event_json.h"

#include <fmt/format.h>

#include <string_view>
#include <type_traits>
#include <utility>

#include "commission_wire/event_json_parts.h"
#include "driver/hex.h"

namespace tiltgate {

using json = nlohmann::json;

namespace {

// Each event's name on the wire: a name of its own, so reordering CommissionEvent changes
// nothing a peer sees. Every alternative must have one (checked below).
template <class Event>
constexpr std::string_view kEventName = "";
template <> constexpr std::string_view kEventName<NoteEvent> = "note";
template <> constexpr std::string_view kEventName<ProgressEvent> = "progress";
template <> constexpr std::string_view kEventName<DeviceFoundEvent> = "device_found";
template <> constexpr std::string_view kEventName<ScanFinishedEvent> = "scan_finished";
template <> constexpr std::string_view kEventName<ExchangeEvent> = "exchange";
template <> constexpr std::string_view kEventName<FailedEvent> = "failed";
template <> constexpr std::string_view kEventName<SensorReadingEvent> = "sensor_reading";
template <> constexpr std::string_view kEventName<WatchRoundEvent> = "watch_round";
template <> constexpr std::string_view kEventName<SettingAcknowledgedEvent> = "setting_acknowledged";
template <> constexpr std::string_view kEventName<SettingAppliedEvent> = "setting_applied";
template <> constexpr std::string_view kEventName<AddressMovedEvent> = "address_moved";
template <> constexpr std::string_view kEventName<SensorRestartedEvent> = "sensor_restarted";
template <> constexpr std::string_view kEventName<ConfigUpdatedEvent> = "config_updated";
template <> constexpr std::string_view kEventName<SettingsReadEvent> = "settings_read";
template <> constexpr std::string_view kEventName<GatewayWarningEvent> = "gateway_warning";

template <std::size_t... I>
constexpr bool every_event_named(std::index_sequence<I...>) {
  return (!kEventName<std::variant_alternative_t<I, CommissionEvent>>.empty() && ...);
}
static_assert(every_event_named(std::make_index_sequence<std::variant_size_v<CommissionEvent>>()),
              "every CommissionEvent needs its kEventName");

// The alternative named `name`, read from `fields`; none when no event has that name.
template <std::size_t... I>
std::optional<CommissionEvent> read_named_event(std::string_view name,
                                                const JsonObjectReader& fields,
                                                std::index_sequence<I...>) {
  std::optional<CommissionEvent> event;
  auto try_one = [&]<std::size_t N>(std::integral_constant<std::size_t, N>) {
    using Event = std::variant_alternative_t<N, CommissionEvent>;
    if (event || kEventName<Event> != name) return;
    Event read;
    read_event_fields(fields, read);
    event.emplace(std::in_place_index<N>, std::move(read));
  };
  (try_one(std::integral_constant<std::size_t, I>()), ...);
  return event;
}

}  // namespace

json event_fields(const NoteEvent& e) { return json{{"warning", e.warning}, {"text", e.text}}; }

void read_event_fields(const JsonObjectReader& r, NoteEvent& e) {
  e.warning = r.boolean("warning");
  e.text = r.string("text");
}

json event_fields(const FailedEvent& e) {
  return json{{"exit_code", e.exit_code}, {"message", e.message}};
}

void read_event_fields(const JsonObjectReader& r, FailedEvent& e) {
  e.exit_code = r.integer<int>("exit_code");
  e.message = r.string("message");
}

json event_fields(const GatewayWarningEvent& e) { return json{{"text", e.text}}; }

void read_event_fields(const JsonObjectReader& r, GatewayWarningEvent& e) {
  e.text = r.string("text");
}

// Bytes as hex_bytes writes them ("01 03 0A"), read back by parse_hex_bytes (driver/hex.h).
json event_fields(const ExchangeEvent& e) {
  return json{{"sent", hex_bytes(e.sent)},
              {"address_bytes", e.address_bytes},
              {"answered", e.answered},
              {"received", hex_bytes(e.received)},
              {"verdict", e.verdict},
              {"rejected_verdict", e.rejected_verdict},
              {"decoded", e.decoded},
              {"refused", e.refused}};
}

void read_event_fields(const JsonObjectReader& r, ExchangeEvent& e) {
  e.sent = r.hex_bytes("sent");
  e.address_bytes = r.integer<std::size_t>("address_bytes");
  e.answered = r.boolean("answered");
  e.received = r.hex_bytes("received");
  e.verdict = r.string("verdict");
  e.rejected_verdict = r.string("rejected_verdict");
  e.decoded = r.string("decoded");
  e.refused = r.boolean("refused");
}

json event_json(const CommissionEvent& event) {
  return std::visit(
      [](const auto& e) {
        json object = event_fields(e);
        object["event"] = std::string(kEventName<std::decay_t<decltype(e)>>);
        return object;
      },
      event);
}

Expected<CommissionEvent, std::string> event_from_json(const json& j) {
  try {
    const JsonObjectReader fields(j, "");
    const std::string name = fields.string("event");
    auto event = read_named_event(name, fields,
                                  std::make_index_sequence<std::variant_size_v<CommissionEvent>>());
    if (!event) return Unexpected{fmt::format("not an event: no event is named \"{}\"", name)};
    return std::move(*event);
  } catch (const std::exception& e) {
    return Unexpected{fmt::format("not an event: {}", e.what())};
  }
}

}  // namespace tiltgate
