// What the Modbus TCP server hands to the rest of the gateway: a request that has already been
// checked against the Modbus spec, and the answer the gateway gives to it. The handler never
// sees a socket or a malformed frame.
#pragma once

#include <boost/asio/awaitable.hpp>
#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "audit/audit_record.h"
#include "driver/expected.h"

namespace tiltgate {

enum class ModbusTable { coil, discrete, input, holding };

// Modbus Application Protocol V1.1b3, section 7 (exception codes).
enum class ModbusException : std::uint8_t {
  illegal_function = 0x01,
  illegal_address = 0x02,
  illegal_value = 0x03,
  device_failure = 0x04,
  busy = 0x06,
  gateway_path_unavailable = 0x0A,
  gateway_target_failed = 0x0B,
};

// One Read Device Identification object (function 43 / MEI type 14): its id and its value, an
// ASCII string. modbus_tcp/device_identification.h lists the ids the gateway uses.
struct DeviceObject {
  std::uint8_t id = 0;
  std::string value;
  friend bool operator==(const DeviceObject&, const DeviceObject&) = default;
};

struct ModbusRequest {
  std::uint16_t transaction_id = 0;
  std::uint8_t unit_id = 0;
  std::uint8_t function = 0;
  ModbusTable table = ModbusTable::holding;
  bool is_write = false;
  std::uint16_t address = 0;
  std::uint16_t count = 0;             // 1 for the single writes 05 and 06
  std::vector<std::uint16_t> registers;  // the values of 06 / 16
  std::vector<bool> bits;                // the values of 05 / 15
  // 43 / 14 Read Device Identification (table, address and count unused): the Read Device ID
  // code (1 basic, 2 regular, 3 extended stream, 4 one object) and the object id.
  std::uint8_t read_device_id_code = 0;
  std::uint8_t object_id = 0;
  // 08 Diagnostics: the sub-function (modbus_tcp/diagnostics.h).
  std::uint16_t diagnostic = 0;
  std::vector<std::uint8_t> adu;         // the whole checked frame, MBAP header included
  WriteOrigin origin;  // writes only: who sent it (the connection fills it in)
};

struct ModbusResponse {
  std::optional<ModbusException> exception;
  // A read answers exactly `count` values in the one that matches its table (registers for
  // 03/04, bits for 01/02); a write leaves both empty on success.
  std::vector<std::uint16_t> registers;
  std::vector<bool> bits;
  // 08: the count asked for in registers[0] (0x0000 and 0x000A echo the request); 11: the
  // status word and the event count in registers[0] and [1].
  // 43 / 14: every identification object of the unit, in id order. The reply encoder picks
  // what the request asks for (category, start, paging) and answers 02 for a missing object.
  std::vector<DeviceObject> device_objects;
};

// A request passed through to a device: the reply PDU (function code and data) the device
// sent, to relay unchanged, or the exception the gateway answers instead.
using ForwardedReply = Expected<std::vector<std::uint8_t>, ModbusException>;

// One connection's way to answer requests at once, on its own thread, without a coroutine:
// what a read needs of the handler's tables it may keep between requests, as long as it
// notices when they change (docs/performance.md, "The Modbus read path"). Used by one
// connection only.
class ModbusReader {
 public:
  virtual ~ModbusReader() = default;
  // True with `response` filled (its buffers reused: a read allocates nothing once they have
  // grown) when the request is answered from what is cached, as it is at `now`; false when it
  // needs handle() instead (a write that waits for its device).
  virtual bool read(const ModbusRequest& request, ModbusResponse& response,
                    std::chrono::steady_clock::time_point now) = 0;
  // The handler's passes_through(), from what is cached.
  virtual bool passes_through(std::uint8_t unit_id) = 0;
};

// Answers checked requests. handle() and forward() run on the server's executor: a write may
// take as long as the sensor needs (other connections are served meanwhile); reader() and
// passes_through() are called from every connection's thread.
class ModbusRequestHandler {
 public:
  virtual ~ModbusRequestHandler() = default;
  virtual boost::asio::awaitable<ModbusResponse> handle(const ModbusRequest& request) = 0;
  // A reader for one new connection; none: every request goes through handle().
  virtual std::unique_ptr<ModbusReader> reader() { return nullptr; }

  // Whether requests for `unit_id` are forwarded to a device ([[bus]] pass_through) instead
  // of answered by handle(). The server then skips its own function and PDU checks (any
  // function passes through) once the MBAP framing is valid.
  virtual bool passes_through(std::uint8_t /*unit_id*/) const { return false; }
  // Forwards the request PDU (function code and data) of a unit that passes through, for the
  // client at `client` (its address: a bus serves its clients' requests in turn); `origin` is
  // who sent it, for the audit trail's record of one that may change the device.
  virtual boost::asio::awaitable<ForwardedReply> forward(std::uint8_t /*unit_id*/,
                                                         std::vector<std::uint8_t> /*pdu*/,
                                                         std::string /*client*/,
                                                         WriteOrigin /*origin*/) {
    co_return Unexpected{ModbusException::gateway_path_unavailable};
  }
};

}  // namespace tiltgate
