// What a simulated slave says of itself to a master that has no profile of it: Report Server
// ID (FC 17, Modbus Application Protocol V1.1b3 section 6.13) and Read Device Identification
// (FC 43 / MEI type 14, section 6.21). Pure: a request PDU in, the reply PDU out.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "modbus_rtu/codec.h"

namespace tiltgate::modbus_rtu {

struct SimulatedIdentification {
  // FC 17: the device-specific server id and the text after the run indicator (always ON);
  // none: FC 17 is an illegal function.
  std::optional<std::uint8_t> server_id;
  std::string additional_data;
  // FC 43 / 14: objects by id, ascending; objects 0..2 are the basic ones, 3..6 regular.
  // Empty: FC 43 is an illegal function.
  std::vector<std::pair<std::uint8_t, std::string>> objects;
};

// The reply PDU (function code first) to an FC 17 request PDU, or an exception PDU.
Bytes answer_report_server_id(const SimulatedIdentification& identification,
                              std::span<const std::uint8_t> pdu);
// The reply PDU to an FC 43 request PDU: stream access (codes 1..3) answers the objects of
// that category and below from the object asked (an unknown one restarts at the first), all in
// one reply; individual access (code 4) the one object or exception 02; other codes and MEI
// types exception 03.
Bytes answer_device_identification(const SimulatedIdentification& identification,
                                   std::span<const std::uint8_t> pdu);

}  // namespace tiltgate::modbus_rtu
