// `tiltgate raw` on a Modbus RTU bus: --function is the Modbus function code, --data the rest of
// the PDU; the slave address and CRC are added (on a modbus-tcp bus the MBAP header), and the
// reply checked and decoded by the codec (modbus_rtu/codec.h).
#pragma once

#include <memory>
#include <string>

#include "driver/family_commands.h"

namespace tiltgate::modbus_rtu {

inline constexpr std::string_view kRawFunctionHelp =
    "modbus-rtu, modbus-tcp: the function code (1..127, e.g. 3 Read Holding Registers with data "
    "00 00 00 02), --data the rest of the PDU; the slave address and CRC are added (modbus-tcp: "
    "the MBAP header)";

Expected<std::unique_ptr<RawExchange>, std::string> make_raw_exchange(const RawSetup& setup);

}  // namespace tiltgate::modbus_rtu
