// The reference the gateway's own reply formatter (modbus_tcp/modbus_reply_format.h) is tested
// against: Modbus TCP replies formatted by libmodbus 3.1.6's modbus_reply and
// modbus_reply_exception. Test code only; the gateway formats its replies itself.
//
// libmodbus 3.1.6 (Debian 12) can only reply by writing to its context's socket, so the
// context gets one end of a socketpair and the reply is read back from the other end. Only
// requests that parse_adu() accepted are handed to modbus_reply: its 3.1.6 request handling has
// memory-safety bugs on malformed frames (CVE-2022-0367 on 0x17, out-of-bounds reads on short
// 07/11 frames).
//
// Function 43 / 14 (Read Device Identification), which libmodbus does not serve, is encoded
// with the gateway's own code (modbus_tcp/device_identification.h), its exceptions too, so it is
// no reference for that function.
//
// Not thread-safe (neither is a libmodbus context).
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "driver/expected.h"
#include "modbus_tcp/modbus_types.h"

struct _modbus;  // libmodbus's modbus_t, kept out of this header

namespace tiltgate::test {

class LibmodbusReference {
 public:
  static Expected<std::unique_ptr<LibmodbusReference>, std::string> create();
  ~LibmodbusReference();
  LibmodbusReference(const LibmodbusReference&) = delete;
  LibmodbusReference& operator=(const LibmodbusReference&) = delete;

  // The reply ADU to `request` carrying `response`. A response that does not fit the request
  // (a read answered with the wrong number of values) is answered with exception 04. Fails,
  // without calling libmodbus, if request.adu is not a frame parse_adu() accepts as this
  // request; fails if libmodbus or the socketpair does.
  Expected<std::vector<std::uint8_t>, std::string> encode(const ModbusRequest& request,
                                                          const ModbusResponse& response);

  // How many times modbus_reply / modbus_reply_exception ran (tests check it stays put; a
  // 43 / 14 reply never counts).
  std::uint64_t libmodbus_calls() const { return libmodbus_calls_; }

 private:
  LibmodbusReference(_modbus* context, int libmodbus_end, int reply_end);
  Expected<std::vector<std::uint8_t>, std::string> read_reply(int sent);
  void discard_stale_bytes();

  _modbus* context_;
  int libmodbus_end_;  // the socket libmodbus writes replies to
  int reply_end_;      // where we read them back
  std::uint64_t libmodbus_calls_ = 0;
};

}  // namespace tiltgate::test
