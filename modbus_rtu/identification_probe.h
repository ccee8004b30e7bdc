// `tiltgate info` on a Modbus RTU device without a profile: what it says of itself, asked with
// Read Device Identification (FC 43 / MEI 14, Modbus Application Protocol V1.1b3 section 6.21:
// the regular stream, else the basic one) and Report Server ID (FC 17, section 6.13). Many
// devices answer neither (exception 01): the text then says so.
#pragma once

#include <boost/asio/awaitable.hpp>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "driver/expected.h"
#include "driver/family_commands.h"
#include "driver/line.h"

namespace tiltgate::modbus_rtu {

// One FC 43 / 14 reply's objects and whether more follow (then from next_object).
struct DeviceIdPage {
  std::vector<std::pair<std::uint8_t, std::string>> objects;
  bool more_follows = false;
  std::uint8_t next_object = 0;
};

// Pure: the reply PDU (function code first, not an exception) of FC 43 / 14, or what is wrong
// with it.
Expected<DeviceIdPage, std::string> parse_device_id_reply(std::span<const std::uint8_t> pdu);
// "vendor:     tiltgate\n" ...: one line an object, named as 6.21 names it.
std::string device_id_text(std::span<const std::pair<std::uint8_t, std::string>> objects);
// The FC 17 reply PDU read as most devices (and libmodbus) lay it out: the server id byte, the
// run indicator (0x00 OFF, 0xFF ON), then device-specific data, shown as text where it is.
std::string server_id_text(std::span<const std::uint8_t> pdu);

// Over MBAP on a modbus-tcp bus (modbus_rtu/adu_framing.h), in RTU frames on modbus-rtu.
boost::asio::awaitable<SelfReport> ask_identification(Line& line, std::string_view protocol,
                                                      std::uint32_t address);

}  // namespace tiltgate::modbus_rtu
