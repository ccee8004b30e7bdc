#include "commission/event_json.h"

#include <fmt/format.h>

#include "driver/hex.h"

namespace tiltgate {

using json = nlohmann::json;

namespace {

template <class... F>
struct Overloaded : F... {
  using F::operator()...;
};
template <class... F>
Overloaded(F...) -> Overloaded<F...>;

json found_json(const FoundSensor& s) {
  return json{{"address", s.address},   {"baud", s.baud},       {"collision", s.collision},
              {"detail", s.detail},     {"model", s.model},     {"serial", s.serial},
              {"firmware", s.firmware},
              {"lock_level", s.lock_level ? json(*s.lock_level) : json(nullptr)}};
}

json found_list_json(const std::vector<FoundSensor>& found) {
  json list = json::array();
  for (const FoundSensor& s : found) list.push_back(found_json(s));
  return list;
}

FoundSensor found_from(const json& j) {
  FoundSensor s;
  s.address = j.at("address").get<std::uint32_t>();
  s.baud = j.at("baud").get<std::uint32_t>();
  s.collision = j.at("collision").get<bool>();
  s.detail = j.at("detail").get<std::string>();
  s.model = j.at("model").get<std::string>();
  s.serial = j.at("serial").get<std::string>();
  s.firmware = j.at("firmware").get<std::string>();
  if (!j.at("lock_level").is_null()) s.lock_level = j.at("lock_level").get<std::uint16_t>();
  return s;
}

std::vector<FoundSensor> found_list_from(const json& j) {
  std::vector<FoundSensor> found;
  for (const json& item : j) found.push_back(found_from(item));
  return found;
}

json finished_json(const ScanFinishedEvent& e) {
  json repeated = json::array();
  for (const RepeatedSensor& r : e.repeated)
    repeated.push_back({{"address", r.address},
                        {"serial", r.serial},
                        {"kept_baud", r.kept_baud},
                        {"other_bauds", r.other_bauds}});
  json tables = json::array();
  for (const SensorTable& t : e.tables)
    tables.push_back({{"address", t.address},
                      {"model", t.model},
                      {"serial", t.serial},
                      {"firmware", t.firmware},
                      {"text", t.text}});
  return json{{"event", "scan_finished"},     {"found", found_list_json(e.found)},
              {"repeated", repeated},          {"probes", e.probes},
              {"took_ms", e.took.count()},     {"configuration", e.configuration},
              {"tables", tables}};
}

ScanFinishedEvent finished_from(const json& j) {
  ScanFinishedEvent e;
  e.found = found_list_from(j.at("found"));
  for (const json& r : j.at("repeated"))
    e.repeated.push_back({r.at("address").get<std::uint32_t>(), r.at("serial").get<std::string>(),
                          r.at("kept_baud").get<std::uint32_t>(),
                          r.at("other_bauds").get<std::vector<std::uint32_t>>()});
  e.probes = j.at("probes").get<std::size_t>();
  e.took = std::chrono::milliseconds(j.at("took_ms").get<std::int64_t>());
  e.configuration = j.at("configuration").get<std::string>();
  for (const json& t : j.at("tables"))
    e.tables.push_back({t.at("address").get<std::uint32_t>(), t.at("model").get<std::string>(),
                        t.at("serial").get<std::string>(), t.at("firmware").get<std::string>(),
                        t.at("text").get<std::string>()});
  return e;
}

json exchange_json(const ExchangeEvent& e) {
  return json{{"event", "exchange"},
              {"sent", hex_bytes(e.sent)},
              {"address_bytes", e.address_bytes},
              {"answered", e.answered},
              {"received", hex_bytes(e.received)},
              {"verdict", e.verdict},
              {"rejected_verdict", e.rejected_verdict},
              {"decoded", e.decoded},
              {"refused", e.refused}};
}

std::vector<std::uint8_t> bytes_from(const json& j) {
  auto bytes = parse_hex_bytes(j.get<std::string>());
  if (!bytes) throw std::invalid_argument("not hex bytes");
  return *bytes;
}

ExchangeEvent exchange_from(const json& j) {
  ExchangeEvent e;
  e.sent = bytes_from(j.at("sent"));
  e.address_bytes = j.at("address_bytes").get<std::size_t>();
  e.answered = j.at("answered").get<bool>();
  e.received = bytes_from(j.at("received"));
  e.verdict = j.at("verdict").get<std::string>();
  e.rejected_verdict = j.at("rejected_verdict").get<std::string>();
  e.decoded = j.at("decoded").get<std::string>();
  e.refused = j.at("refused").get<bool>();
  return e;
}

CommissionEvent event_from(const json& j) {
  const std::string kind = j.at("event").get<std::string>();
  if (kind == "note") return NoteEvent{j.at("warning").get<bool>(), j.at("text").get<std::string>()};
  if (kind == "progress")
    return ProgressEvent{j.at("done").get<std::size_t>(), j.at("total").get<std::size_t>(),
                         j.at("baud").get<std::uint32_t>(), found_list_from(j.at("found"))};
  if (kind == "device_found") return DeviceFoundEvent{found_from(j.at("sensor"))};
  if (kind == "scan_finished") return finished_from(j);
  if (kind == "exchange") return exchange_from(j);
  if (kind == "failed")
    return FailedEvent{j.at("exit_code").get<int>(), j.at("message").get<std::string>()};
  throw std::invalid_argument(fmt::format("no event \"{}\"", kind));
}

}  // namespace

json event_json(const CommissionEvent& event) {
  return std::visit(
      Overloaded{
          [](const NoteEvent& e) {
            return json{{"event", "note"}, {"warning", e.warning}, {"text", e.text}};
          },
          [](const ProgressEvent& e) {
            return json{{"event", "progress"}, {"done", e.done},          {"total", e.total},
                        {"baud", e.baud},       {"found", found_list_json(e.found)}};
          },
          [](const DeviceFoundEvent& e) {
            return json{{"event", "device_found"}, {"sensor", found_json(e.sensor)}};
          },
          [](const ScanFinishedEvent& e) { return finished_json(e); },
          [](const ExchangeEvent& e) { return exchange_json(e); },
          [](const FailedEvent& e) {
            return json{{"event", "failed"}, {"exit_code", e.exit_code}, {"message", e.message}};
          },
      },
      event);
}

Expected<CommissionEvent, std::string> event_from_json(const json& j) {
  try {
    return event_from(j);
  } catch (const std::exception& e) {
    return Unexpected{fmt::format("not an event: {}", e.what())};
  }
}

}  // namespace tiltgate
