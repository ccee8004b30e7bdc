// Modbus TCP requests, checked before anything else sees them: the MBAP header, the function,
// the PDU layout, the quantities and the address range. Pure (no I/O, no libmodbus), so every
// malformed frame can be tested and fuzzed on its own.
//
// References: "Modbus Messaging on TCP/IP Implementation Guide V1.0b" (MBAP, section 3.1.3)
// and "Modbus Application Protocol Specification V1.1b3" (functions, section 6).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <variant>
#include <vector>

#include "driver/expected.h"
#include "driver/modbus_reads.h"
#include "modbus_tcp/modbus_types.h"

namespace tiltgate {

// Transaction id (2), protocol id (2), length (2), unit id (1).
inline constexpr std::size_t mbap_header_size = 7;
// The MBAP header plus the largest PDU (253 bytes, Application Protocol section 4.1).
inline constexpr std::size_t max_adu_size = 260;

namespace modbus_function {
inline constexpr std::uint8_t read_coils = 0x01;
inline constexpr std::uint8_t read_discrete_inputs = 0x02;
inline constexpr std::uint8_t read_holding_registers = 0x03;
inline constexpr std::uint8_t read_input_registers = 0x04;
inline constexpr std::uint8_t write_single_coil = 0x05;
inline constexpr std::uint8_t write_single_register = 0x06;
// Diagnostics and Get Comm Event Counter (modbus_tcp/diagnostics.h).
inline constexpr std::uint8_t diagnostics = 0x08;
inline constexpr std::uint8_t get_comm_event_counter = 0x0B;
inline constexpr std::uint8_t write_multiple_coils = 0x0F;
inline constexpr std::uint8_t write_multiple_registers = 0x10;
// Encapsulated Interface Transport; the gateway serves MEI type 14, Read Device
// Identification (modbus_tcp/device_identification.h).
inline constexpr std::uint8_t encapsulated_interface = 0x2B;
}  // namespace modbus_function

// Why a byte stream cannot be cut into frames; the connection has to be closed.
enum class FramingError {
  protocol_id,  // MBAP protocol id is not 0 (Modbus)
  length,       // MBAP length outside 2..254 (unit id + function + at most 252 data bytes)
};
const char* to_string(FramingError error);

// The size of a whole ADU, worked out from its MBAP header.
Expected<std::size_t, FramingError> adu_size(
    std::span<const std::uint8_t, mbap_header_size> header);

// A request the parser answers itself with an exception, without the handler.
struct RejectedRequest {
  ModbusException exception;
  std::vector<std::uint8_t> reply;  // the whole exception ADU
};

// What one whole ADU turns out to be.
using ParsedAdu = std::variant<ModbusRequest, RejectedRequest, FramingError>;
ParsedAdu parse_adu(std::span<const std::uint8_t> adu);
// Why an ADU is not a request for the handler.
using AduProblem = std::variant<RejectedRequest, FramingError>;
// The same into `request`, reusing its vectors: a connection parses every request into one
// object, so a read allocates nothing. None when `request` now holds the accepted request.
std::optional<AduProblem> parse_adu_into(std::span<const std::uint8_t> adu,
                                         ModbusRequest& request);


// The exception reply to an ADU (at least its MBAP header and function code).
std::vector<std::uint8_t> exception_reply(std::span<const std::uint8_t> adu, ModbusException code);

// The reply to a request passed through to a device: the request's MBAP header (transaction
// id, protocol id, unit id) with the device's reply PDU and the length that fits it.
std::vector<std::uint8_t> relayed_reply(std::span<const std::uint8_t> adu,
                                        std::span<const std::uint8_t> pdu);

// Cuts a TCP byte stream into ADUs by the MBAP length field. Resumable and I/O-free: the
// connection reads into space(), commits what arrived, and takes whole frames from next().
// Its buffer holds many requests, so one read takes in every request a client pipelined.
class ModbusFrameAssembler {
 public:
  struct NeedMore {};
  using Next = std::variant<NeedMore, std::span<const std::uint8_t>, FramingError>;

  // The front of the stream: a whole ADU (valid until pop() or space()), a need for more
  // bytes, or a header that makes framing impossible.
  Next next() const;
  // Drops the ADU next() returned.
  void pop();
  // Where the next read goes: at least max_adu_size bytes, never empty while next() says
  // NeedMore (an incomplete frame is always shorter than that).
  std::span<std::uint8_t> space();
  void commit(std::size_t n) { end_ += n; }
  std::size_t buffered() const { return end_ - start_; }

 private:
  std::array<std::uint8_t, 16 * max_adu_size> buffer_{};
  std::size_t start_ = 0;  // the front of the stream
  std::size_t end_ = 0;    // the end of what was read
};

}  // namespace tiltgate
