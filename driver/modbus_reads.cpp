#include "driver/modbus_reads.h"

namespace tiltgate {

// Application Protocol V1.1b3 section 6.21: MEI type 14 reads the device identification.
constexpr std::uint8_t kMeiReadDeviceIdentification = 0x0E;

bool reads_only(std::span<const std::uint8_t> pdu) {
  if (pdu.empty()) return false;
  switch (pdu[0]) {
    case 0x01:  // read coils
    case 0x02:  // read discrete inputs
    case 0x03:  // read holding registers
    case 0x04:  // read input registers
    case 0x07:  // read exception status
    case 0x0B:  // get comm event counter
    case 0x0C:  // get comm event log
    case 0x11:  // report server id
    case 0x14:  // read file record
    case 0x18:  // read FIFO queue
      return true;
    case 0x08: {  // diagnostics: the sub-functions that only return data
      if (pdu.size() < 3) return false;
      const unsigned sub_function = (unsigned(pdu[1]) << 8) | pdu[2];
      // 0000 return query data, 0002 return diagnostic register, 000B..0012 the counts.
      return sub_function == 0x0000 || sub_function == 0x0002 ||
             (sub_function >= 0x000B && sub_function <= 0x0012);
    }
    case 0x2B:  // encapsulated interface
      return pdu.size() >= 2 && pdu[1] == kMeiReadDeviceIdentification;
    default:
      return false;
  }
}

}  // namespace tiltgate
