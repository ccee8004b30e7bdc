// Modbus RTU frames (Modbus over Serial Line V1.02; Modbus Application Protocol V1.1b3): the
// requests the gateway sends and the checks on what comes back. Pure: bytes in, typed values or
// typed errors out, no I/O, so it can be unit tested and fuzzed on its own.
//
// A frame (ADU) is: slave address, PDU (function code + data), CRC-16 low byte first. Every
// other multi-byte field is big-endian.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "driver/expected.h"

namespace tiltgate::modbus_rtu {

using Bytes = std::vector<std::uint8_t>;

// Function codes (Application Protocol 6.3, 6.4, 6.6, 6.12, 6.13, 6.21).
inline constexpr std::uint8_t kReadHoldingRegisters = 0x03;
inline constexpr std::uint8_t kReadInputRegisters = 0x04;
inline constexpr std::uint8_t kWriteSingleRegister = 0x06;
inline constexpr std::uint8_t kWriteMultipleRegisters = 0x10;
// Report Server ID (6.13) and Read Device Identification, MEI type 14 of function 43 (6.21):
// what a device says of itself without a register map.
inline constexpr std::uint8_t kReportServerId = 0x11;
inline constexpr std::uint8_t kEncapsulatedInterface = 0x2B;
inline constexpr std::uint8_t kMeiReadDeviceId = 0x0E;
// An exception reply carries the request's function code with this bit set (7.).
inline constexpr std::uint8_t kExceptionBit = 0x80;

inline constexpr std::uint8_t kBroadcastAddress = 0;  // Serial Line 2.2: writes only, no reply
inline constexpr std::uint8_t kMaxSlaveAddress = 247;  // 248..255 are reserved
inline constexpr std::size_t kMaxFrameSize = 256;      // Serial Line 2.5.1.1
inline constexpr std::size_t kMaxPduSize = 253;
inline constexpr std::uint16_t kMaxReadCount = 125;   // FC 3/4: 0x7D registers
inline constexpr std::uint16_t kMaxWriteCount = 123;  // FC 16: 0x7B registers

// Exception codes (Application Protocol 7.).
enum class ExceptionCode : std::uint8_t {
  illegal_function = 0x01,
  illegal_data_address = 0x02,
  illegal_data_value = 0x03,
  device_failure = 0x04,
};

// An exception code's name in the Application Protocol (7.): "illegal data address".
const char* exception_name(std::uint8_t code);

enum class RegisterBank : std::uint8_t {
  holding = kReadHoldingRegisters,
  input = kReadInputRegisters,
};

enum class CodecError {
  // building a request
  bad_slave,     // not 1..247 (0 too for a write, which may broadcast)
  bad_count,     // a register count outside the function's limits
  bad_range,     // address + count past 65535
  bad_pdu,       // a pass-through PDU that is empty or longer than 253 bytes
  // checking a reply
  too_short,       // fewer bytes than the smallest frame of its kind
  crc_mismatch,    // the CRC does not match the bytes
  wrong_slave,     // from another slave than the one asked
  wrong_function,  // neither the request's function code nor its exception
  bad_byte_count,  // FC 3/4: the byte count is not twice the registers asked for
  bad_length,      // the frame is longer or shorter than its function says
  echo_mismatch,   // FC 6/16: the echoed address, value or count differ from the request
};

const char* to_string(CodecError error);

struct Request {
  std::uint8_t slave = 0;
  std::uint8_t function = 0;
  // The RTU frame, CRC included: what goes on a serial line. Over Modbus TCP its PDU goes in
  // an MBAP frame instead (modbus_rtu/mbap_codec.h).
  Bytes frame;
};

struct Reply {
  std::uint8_t slave = 0;
  std::uint8_t function = 0;  // the request's function code, without the exception bit
  std::optional<std::uint8_t> exception;  // set when the device refused the request
  std::vector<std::uint16_t> registers;   // FC 3/4: the registers read, in order
  Bytes pdu;  // function code and data as received (no address, no CRC): a pass-through relays it
};

Expected<Request, CodecError> read_request(std::uint8_t slave, RegisterBank bank,
                                           std::uint16_t address, std::uint16_t count);
// FC 6. Slave 0 broadcasts (no reply comes).
Expected<Request, CodecError> write_single_request(std::uint8_t slave, std::uint16_t address,
                                                   std::uint16_t value);
// FC 16, 1..123 registers. Slave 0 broadcasts.
Expected<Request, CodecError> write_multiple_request(std::uint8_t slave, std::uint16_t address,
                                                     std::span<const std::uint16_t> values);
// Any PDU (function code and data) for `slave`, unchanged: Modbus TCP pass-through.
Expected<Request, CodecError> raw_request(std::uint8_t slave, std::span<const std::uint8_t> pdu);

// Checks `frame` (one whole frame, CRC included) as the reply to `request`: slave, function,
// CRC, lengths, byte count and, for writes, the echo. An exception reply is a valid Reply.
Expected<Reply, CodecError> parse_reply(const Request& request, std::span<const std::uint8_t> frame);
// The same checks on a reply's PDU alone (function code and data; no address, no CRC), for
// framings that carry the address and the integrity check elsewhere (Modbus TCP's MBAP
// header, modbus_rtu/mbap_codec.h).
Expected<Reply, CodecError> parse_reply_pdu(const Request& request,
                                            std::span<const std::uint8_t> pdu);

// The request's PDU: its frame without the address and the CRC.
std::span<const std::uint8_t> request_pdu(const Request& request);
// The same request for another address, unchecked: Modbus TCP unit ids take every value
// 0..255, where the builders above accept the serial line's slave addresses only.
Request readdressed(const Request& request, std::uint8_t slave);

// An exception reply's frame: what a slave sends when it refuses a request.
Bytes exception_frame(std::uint8_t slave, std::uint8_t function, ExceptionCode code);
// The same reply's PDU: the function code with the exception bit, and the code.
Bytes exception_pdu(std::uint8_t function, ExceptionCode code);

}  // namespace tiltgate::modbus_rtu
