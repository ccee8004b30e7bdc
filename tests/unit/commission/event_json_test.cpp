// The engine's events as JSON (commission_wire/event_json.h), as the control socket streams them to a
// command line: each event's wire form spelled out, read back to the same event through text,
// and every field of every event refused when left out or of the wrong type.
#include <doctest/doctest.h>

#include <set>

#include "commission_wire/event_json.h"
#include "unit/commission/support/aggregate_fields.h"
#include "unit/commission/support/json_fields_probe.h"

namespace tiltgate {
namespace {

using nlohmann::json;

// One event with a value other than its default in every field, and its JSON as it must be.
struct EventCase {
  CommissionEvent event;
  json wire;
};

FoundSensor found_sensor() {
  return {223, 38400, true, "CRC error at 38400", "h6", "962285", "Rev A.8", 2};
}
const char* kFoundSensorJson = R"({"address": 223, "baud": 38400, "collision": true,
  "detail": "CRC error at 38400", "model": "h6", "serial": "962285", "firmware": "Rev A.8",
  "lock_level": 2})";

SensorReadingEvent sensor_reading() {
  SensorReadingEvent e;
  e.address = 224;
  e.model = "h6";
  e.device_model = "H6-X";
  e.serial = "10001";
  e.firmware = "2.1";
  e.lock_level = 3;
  e.result = PollResult::refused;
  e.status = "refused: NAK 2, locked";
  e.angle_x = 0.1;
  e.angle_y = -12.345678901234567;
  e.age = std::chrono::milliseconds(250);
  e.readings_per_second = 19.5;
  e.polled = std::chrono::system_clock::time_point(std::chrono::milliseconds(1765000000123));
  e.self_report = "vendor: ACME\n";
  return e;
}
const char* kSensorReadingJson = R"({"address": 224, "model": "h6", "device_model": "H6-X",
  "serial": "10001", "firmware": "2.1", "lock_level": 3, "result": "refused",
  "status": "refused: NAK 2, locked", "angle_x": 0.1, "angle_y": -12.345678901234567,
  "age_ms": 250, "readings_per_second": 19.5, "polled_ms": 1765000000123,
  "self_report": "vendor: ACME\n"})";

json wire(const std::string& text) { return json::parse(text); }

std::vector<EventCase> event_cases() {
  const std::string found = kFoundSensorJson;
  const std::string reading = kSensorReadingJson;
  return {
      {NoteEvent{true, "--broadcast works only with one sensor"},
       wire(R"({"event": "note", "warning": true,
               "text": "--broadcast works only with one sensor"})")},
      {ProgressEvent{17, 256, 9600, {found_sensor()}},
       wire(R"({"event": "progress", "done": 17, "total": 256, "baud": 9600, "found": [)" + found +
            "]}")},
      {DeviceFoundEvent{found_sensor()},
       wire(R"({"event": "device_found", "sensor": )" + found + "}")},
      {ScanFinishedEvent{{found_sensor()},
                         {{1, "10001", 38400, {4800, 9600}}},
                         512,
                         std::chrono::milliseconds(4100),
                         "[[bus]]\nport = \"/dev/ttyUSB0\"\n",
                         {{223, "h6", "962285", "Rev A.8", "[[sensor]]\nname = \"sensor_223\"\n",
                           "", 4}}},
       wire(R"({"event": "scan_finished", "found": [)" + found + R"(],
               "repeated": [{"address": 1, "serial": "10001", "kept_baud": 38400,
                             "other_bauds": [4800, 9600]}],
               "probes": 512, "took_ms": 4100,
               "configuration": "[[bus]]\nport = \"/dev/ttyUSB0\"\n",
               "tables": [{"address": 223, "model": "h6", "serial": "962285",
                           "firmware": "Rev A.8", "text": "[[sensor]]\nname = \"sensor_223\"\n",
                           "configured_as": "", "proposed_unit_id": 4}]})")},
      {ExchangeEvent{{0x01, 0x03, 0x00, 0x0A}, 1, true, {0x01, 0x83, 0x02, 0xC0, 0xF1},
                     "CRC ok", "CRC error", "exception 2, illegal data address", true},
       wire(R"({"event": "exchange", "sent": "01 03 00 0A", "address_bytes": 1, "answered": true,
               "received": "01 83 02 C0 F1", "verdict": "CRC ok", "rejected_verdict": "CRC error",
               "decoded": "exception 2, illegal data address", "refused": true})")},
      {FailedEvent{2, "--from 300 is above the protocol's 255"},
       wire(R"({"event": "failed", "exit_code": 2,
               "message": "--from 300 is above the protocol's 255"})")},
      {sensor_reading(), [&] {
         json j = wire(reading);
         j["event"] = "sensor_reading";
         return j;
       }()},
      {WatchRoundEvent{42, {sensor_reading()}, {"model found: h6"}},
       wire(R"({"event": "watch_round", "round": 42, "readings": [)" + reading + R"(],
               "notes": ["model found: h6"]})")},
      {SettingAcknowledgedEvent{223, "filter", 3.0, 5.5, "nak", std::uint8_t{4}, "locked"},
       wire(R"({"event": "setting_acknowledged", "address": 223, "setting": "filter",
               "old_value": 3.0, "value": 5.5, "result": "nak", "refusal_code": 4,
               "detail": "locked"})")},
      {SettingAppliedEvent{"zero-here", true, 7},
       wire(R"({"event": "setting_applied", "setting": "zero-here", "permanent": true,
               "address": 7})")},
      {AddressMovedEvent{223, 7, "north_wall"},
       wire(R"({"event": "address_moved", "from": 223, "to": 7,
               "gateway_sensor": "north_wall"})")},
      {SensorRestartedEvent{115200, false, 9600},
       wire(R"({"event": "sensor_restarted", "baud": 115200, "line_follows": false,
               "bus_baud": 9600})")},
      {ConfigUpdatedEvent{"/etc/tiltgate/tiltgate.toml",
                          {"updated /etc/tiltgate/tiltgate.toml: sensor north_wall address 223 -> 7"}},
       wire(R"({"event": "config_updated", "file": "/etc/tiltgate/tiltgate.toml",
               "changes": ["updated /etc/tiltgate/tiltgate.toml: sensor north_wall address 223 -> 7"]})")},
      {SettingsReadEvent{7, {{"filter", 5.5}, {"offset", std::nullopt}}},
       wire(R"({"event": "settings_read", "address": 7,
               "settings": [{"name": "filter", "value": 5.5}, {"name": "offset", "value": null}]})")},
      {GatewayWarningEvent{"the gateway polls north_wall at 223 until its next reload"},
       wire(R"({"event": "gateway_warning",
               "text": "the gateway polls north_wall at 223 until its next reload"})")},
  };
}

TEST_CASE("every kind of engine event has its wire form checked here") {
  std::set<std::size_t> kinds;
  for (const EventCase& c : event_cases()) kinds.insert(c.event.index());
  CHECK(kinds.size() == std::variant_size_v<CommissionEvent>);
}

TEST_CASE("every field of every event and of the structs in it has its place on the wire") {
  for (const EventCase& c : event_cases()) {
    CAPTURE(c.wire.dump());
    const std::size_t fields = std::visit(
        [](const auto& e) { return test::aggregate_field_count<std::decay_t<decltype(e)>>(); },
        c.event);
    CHECK(c.wire.size() == fields + 1);  // and "event"
  }
  json finished;
  for (const EventCase& c : event_cases())
    if (c.wire.at("event") == "scan_finished") finished = c.wire;
  CHECK(finished.at("found")[0].size() == test::aggregate_field_count<FoundSensor>());
  CHECK(finished.at("repeated")[0].size() == test::aggregate_field_count<RepeatedSensor>());
  CHECK(finished.at("tables")[0].size() == test::aggregate_field_count<SensorTable>());
  const json read = event_json(SettingsReadEvent{1, {{"filter", 1.0}}});
  CHECK(read.at("settings")[0].size() == test::aggregate_field_count<SettingValue>());
}

TEST_CASE("each event is written as its fields by name, every field set") {
  for (const EventCase& c : event_cases()) {
    CAPTURE(c.wire.dump());
    CHECK(event_json(c.event) == c.wire);
  }
}

TEST_CASE("each event read back from its text is the event written, field for field") {
  for (const EventCase& c : event_cases()) {
    CAPTURE(c.wire.dump());
    const auto back = event_from_json(json::parse(event_json(c.event).dump()));
    REQUIRE_MESSAGE(back.has_value(), back.error());
    CHECK(back->index() == c.event.index());
    CHECK(event_json(*back) == c.wire);
  }
}

TEST_CASE("a reading's poll time and optionals come back as they went, none as null") {
  const auto back = event_from_json(json::parse(event_json(sensor_reading()).dump()));
  REQUIRE(back.has_value());
  const auto& reading = std::get<SensorReadingEvent>(*back);
  CHECK(reading.polled == sensor_reading().polled);
  CHECK(reading.age == std::chrono::milliseconds(250));
  CHECK(reading.angle_x == 0.1);
  CHECK(reading.angle_y == -12.345678901234567);
  CHECK(reading.result == PollResult::refused);

  SensorReadingEvent none;  // every optional empty
  const json written = event_json(none);
  for (const char* key : {"lock_level", "angle_x", "angle_y", "age_ms", "readings_per_second"})
    CHECK(written.at(key).is_null());
  const auto empty = event_from_json(written);
  REQUIRE(empty.has_value());
  const auto& read = std::get<SensorReadingEvent>(*empty);
  CHECK_FALSE(read.lock_level.has_value());
  CHECK_FALSE(read.angle_x.has_value());
  CHECK_FALSE(read.age.has_value());
  CHECK_FALSE(read.readings_per_second.has_value());
}

TEST_CASE("every poll result goes by its own name and comes back") {
  for (PollResult result :
       {PollResult::reading, PollResult::refused, PollResult::silent, PollResult::no_reading}) {
    SensorReadingEvent e;
    e.result = result;
    const auto back = event_from_json(event_json(e));
    REQUIRE(back.has_value());
    CHECK(std::get<SensorReadingEvent>(*back).result == result);
  }
  CHECK(event_json(SensorReadingEvent{}).at("result") == "silent");
  json unknown = event_json(SensorReadingEvent{});
  unknown["result"] = "asleep";
  const auto refused = event_from_json(unknown);
  REQUIRE_FALSE(refused.has_value());
  CHECK(refused.error().find("\"result\"") != std::string::npos);
  CHECK(refused.error().find("asleep") != std::string::npos);
}

// A scan's table's marks came after protocol 3 first went out: an older gateway sends neither.
bool added_later(const std::string& path) {
  return path.ends_with("configured_as") || path.ends_with("proposed_unit_id");
}

TEST_CASE("any field left out of any event is an error naming the field") {
  for (const EventCase& c : event_cases())
    for (const test::JsonLeaf& leaf : test::json_leaves(c.wire)) {
      if (!leaf.in_object || added_later(leaf.path)) continue;
      CAPTURE(leaf.path);
      const auto read = event_from_json(test::without(c.wire, leaf));
      REQUIRE_FALSE(read.has_value());
      CHECK(read.error().find('"' + leaf.path + '"') != std::string::npos);
    }
}

TEST_CASE("any field of the wrong type in any event is an error naming the field") {
  for (const EventCase& c : event_cases())
    for (const test::JsonLeaf& leaf : test::json_leaves(c.wire)) {
      CAPTURE(leaf.path);
      const auto read = event_from_json(test::with(c.wire, leaf, json::object()));
      REQUIRE_FALSE(read.has_value());
      CHECK(read.error().find('"' + leaf.path + '"') != std::string::npos);
    }
  // A number where a string belongs, a string where a number does, a number for a flag.
  const auto text_as_number = event_from_json(wire(R"({"event": "note", "warning": 0, "text": 5})"));
  REQUIRE_FALSE(text_as_number.has_value());
  CHECK(text_as_number.error() == "not an event: field \"warning\": expected true or false, got an integer");
  const auto number_as_text = event_from_json(wire(R"({"event": "failed", "exit_code": "2", "message": ""})"));
  REQUIRE_FALSE(number_as_text.has_value());
  CHECK(number_as_text.error() ==
        "not an event: field \"exit_code\": expected an integer from -2147483648 to 2147483647, "
        "got a string");
}

TEST_CASE("an integer outside its field's range, or with a fraction, is an error, never cut") {
  auto read_progress = [](json baud) {
    json j = event_json(ProgressEvent{1, 2, 9600, {found_sensor()}});
    j["found"][0]["baud"] = std::move(baud);
    return event_from_json(j);
  };
  CHECK(read_progress(-1).error() ==
        "not an event: field \"found[0].baud\": expected an integer from 0 to 4294967295, got an "
        "integer");
  CHECK_FALSE(read_progress(4294967296).has_value());
  CHECK_FALSE(read_progress(9600.5).has_value());
  CHECK(read_progress(4294967295).has_value());

  json refusal = event_json(SettingAcknowledgedEvent{1, "filter", std::nullopt, 1, "nak", 4, ""});
  refusal["refusal_code"] = 256;
  CHECK_FALSE(event_from_json(refusal).has_value());

  json far = event_json(sensor_reading());
  far["polled_ms"] = std::int64_t{9'000'000'000'000'000'000};  // beyond system_clock's reach
  const auto wild = event_from_json(far);
  REQUIRE_FALSE(wild.has_value());
  CHECK(wild.error().find("\"polled_ms\"") != std::string::npos);
}

TEST_CASE("an unknown event name is an error naming it") {
  const auto read = event_from_json(wire(R"({"event": "teleported", "text": "x"})"));
  REQUIRE_FALSE(read.has_value());
  CHECK(read.error() == "not an event: no event is named \"teleported\"");
}

TEST_CASE("bytes that are not hex are an error naming the field") {
  for (const char* bad : {"01 0G", "010", "0x", "01;02"}) {
    CAPTURE(bad);
    json j = event_json(ExchangeEvent{{0x01}, 0, true, {0x02}, "", "", "", false});
    j["received"] = bad;
    const auto read = event_from_json(j);
    REQUIRE_FALSE(read.has_value());
    CHECK(read.error().find("\"received\": expected hex bytes") != std::string::npos);
  }
  json none_sent = event_json(ExchangeEvent{});
  CHECK(none_sent.at("sent") == "");
  CHECK(event_from_json(none_sent).has_value());
}

TEST_CASE("a JSON value that is not an object is an error, never an exception") {
  for (const json& value : {json::array({1, 2}), json("note"), json(nullptr), json(5)}) {
    CAPTURE(value.dump());
    Expected<CommissionEvent, std::string> read = CommissionEvent{FailedEvent{}};
    CHECK_NOTHROW(read = event_from_json(value));
    REQUIRE_FALSE(read.has_value());
    CHECK(read.error().rfind("not an event: expected a JSON object, got ", 0) == 0);
  }
  const auto nested = event_from_json(wire(R"({"event": "device_found", "sensor": [1]})"));
  REQUIRE_FALSE(nested.has_value());
  CHECK(nested.error() == "not an event: field \"sensor\": expected an object, got an array");
}

TEST_CASE("a scan's tables from a gateway before their marks read unmarked, nothing proposed") {
  for (const EventCase& c : event_cases())
    for (const test::JsonLeaf& leaf : test::json_leaves(c.wire)) {
      if (!leaf.in_object || !added_later(leaf.path)) continue;
      CAPTURE(leaf.path);
      const auto read = event_from_json(test::without(c.wire, leaf));
      REQUIRE(read.has_value());
      const auto* finished = std::get_if<ScanFinishedEvent>(&*read);
      REQUIRE(finished != nullptr);
      REQUIRE(finished->tables.size() == 1);
      const SensorTable& table = finished->tables[0];
      if (leaf.path.ends_with("configured_as")) {
        CHECK(table.configured_as.empty());
      } else {
        CHECK(table.proposed_unit_id == 0);
      }
    }
}

}  // namespace
}  // namespace tiltgate
