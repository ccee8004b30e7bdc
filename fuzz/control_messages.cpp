// The control socket's lines (control/control_protocol.h) and the JSON they carry
// (commission_wire/command_request.h, commission_wire/event_json.h): the gateway reads what any
// process of the socket's group sends, the command line what the gateway sends. Each reader
// must answer a value or a reason, never crash, hang or read out of bounds; and what it accepts
// must write back to JSON that reads back the same.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

#include "commission_wire/command_request.h"
#include "commission_wire/event_json.h"
#include "control/control_protocol.h"

namespace {

template <class Read, class Write>
void round_trip(std::string_view text, Read read, Write write) {
  const nlohmann::json json = nlohmann::json::parse(text, nullptr, false);
  if (json.is_discarded()) return;
  const auto value = read(json);
  if (!value) return;
  const nlohmann::json written = write(*value);
  const auto again = read(written);
  if (!again || write(*again) != written) std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view line(reinterpret_cast<const char*>(data), size);
  if (const auto command = tiltgate::control::parse_command(line)) {
    if (const auto* run = std::get_if<tiltgate::control::Run>(&*command))
      round_trip(run->request, tiltgate::request_from_json, tiltgate::request_json);
  }
  if (const auto gateway = tiltgate::control::parse_gateway(line)) {
    if (const auto* event = std::get_if<tiltgate::control::Event>(&*gateway))
      round_trip(event->json, tiltgate::event_from_json, [](const tiltgate::CommissionEvent& e) {
        return tiltgate::event_json(e);
      });
  }
  // The JSON alone, as either reader takes it.
  round_trip(line, tiltgate::request_from_json, tiltgate::request_json);
  round_trip(line, tiltgate::event_from_json,
             [](const tiltgate::CommissionEvent& e) { return tiltgate::event_json(e); });
  return 0;
}
