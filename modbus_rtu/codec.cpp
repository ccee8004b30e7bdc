#include "modbus_rtu/codec.h"

#include <algorithm>

#include "modbus_rtu/big_endian.h"
#include "modbus_rtu/crc.h"

namespace tiltgate::modbus_rtu {
namespace {

bool is_slave(std::uint8_t slave) { return slave >= 1 && slave <= kMaxSlaveAddress; }
bool is_slave_or_broadcast(std::uint8_t slave) { return slave <= kMaxSlaveAddress; }

bool fits(std::uint16_t address, std::size_t count) { return address + count <= 0x10000; }

Request finish(std::uint8_t slave, Bytes frame) {
  const std::uint8_t function = frame[1];
  append_crc(frame);
  return Request{slave, function, std::move(frame)};
}

// The reply's data once function and framing are known good; `pdu` is the reply's PDU
// (function code first), the request's PDU is its frame's bytes 1..
Expected<Done, CodecError> check_data(const Request& request, std::span<const std::uint8_t> pdu) {
  const std::span<const std::uint8_t> sent = request.frame;
  switch (request.function) {
    case kReadHoldingRegisters:
    case kReadInputRegisters: {
      if (pdu[1] != 2 * get_u16(sent, 4)) return Unexpected{CodecError::bad_byte_count};
      if (pdu.size() != 2u + pdu[1]) return Unexpected{CodecError::bad_length};
      return Done{};
    }
    case kWriteSingleRegister:
    case kWriteMultipleRegisters:
      // FC 6 echoes address and value, FC 16 address and count: the request's PDU bytes 1..4.
      if (pdu.size() != 5) return Unexpected{CodecError::bad_length};
      for (std::size_t i = 1; i < 5; ++i)
        if (pdu[i] != sent[i + 1]) return Unexpected{CodecError::echo_mismatch};
      return Done{};
    default:
      return Done{};  // a pass-through: framing checked, the data is the client's business
  }
}

}  // namespace

const char* exception_name(std::uint8_t code) {
  switch (code) {
    case 0x01: return "illegal function";
    case 0x02: return "illegal data address";
    case 0x03: return "illegal data value";
    case 0x04: return "server device failure";
    case 0x05: return "acknowledge";
    case 0x06: return "server device busy";
    case 0x08: return "memory parity error";
    case 0x0A: return "gateway path unavailable";
    case 0x0B: return "gateway target device failed to respond";
    default: return "not a standard exception code";
  }
}

const char* to_string(CodecError error) {
  switch (error) {
    case CodecError::bad_slave: return "slave address out of range";
    case CodecError::bad_count: return "register count out of range";
    case CodecError::bad_range: return "registers past address 65535";
    case CodecError::bad_pdu: return "PDU empty or longer than 253 bytes";
    case CodecError::too_short: return "reply too short";
    case CodecError::crc_mismatch: return "CRC mismatch";
    case CodecError::wrong_slave: return "reply from another slave";
    case CodecError::wrong_function: return "reply to another function";
    case CodecError::bad_byte_count: return "byte count does not match the registers asked for";
    case CodecError::bad_length: return "reply length does not match its function";
    case CodecError::echo_mismatch: return "write reply does not echo the request";
  }
  return "?";
}

Expected<Request, CodecError> read_request(std::uint8_t slave, RegisterBank bank,
                                           std::uint16_t address, std::uint16_t count) {
  if (!is_slave(slave)) return Unexpected{CodecError::bad_slave};
  if (count < 1 || count > kMaxReadCount) return Unexpected{CodecError::bad_count};
  if (!fits(address, count)) return Unexpected{CodecError::bad_range};
  Bytes frame{slave, static_cast<std::uint8_t>(bank)};
  put_u16(frame, address);
  put_u16(frame, count);
  return finish(slave, std::move(frame));
}

Expected<Request, CodecError> write_single_request(std::uint8_t slave, std::uint16_t address,
                                                   std::uint16_t value) {
  if (!is_slave_or_broadcast(slave)) return Unexpected{CodecError::bad_slave};
  Bytes frame{slave, kWriteSingleRegister};
  put_u16(frame, address);
  put_u16(frame, value);
  return finish(slave, std::move(frame));
}

Expected<Request, CodecError> write_multiple_request(std::uint8_t slave, std::uint16_t address,
                                                     std::span<const std::uint16_t> values) {
  if (!is_slave_or_broadcast(slave)) return Unexpected{CodecError::bad_slave};
  if (values.empty() || values.size() > kMaxWriteCount) return Unexpected{CodecError::bad_count};
  if (!fits(address, values.size())) return Unexpected{CodecError::bad_range};
  Bytes frame{slave, kWriteMultipleRegisters};
  put_u16(frame, address);
  put_u16(frame, static_cast<std::uint16_t>(values.size()));
  frame.push_back(static_cast<std::uint8_t>(2 * values.size()));
  for (std::uint16_t v : values) put_u16(frame, v);
  return finish(slave, std::move(frame));
}

Expected<Request, CodecError> raw_request(std::uint8_t slave, std::span<const std::uint8_t> pdu) {
  if (!is_slave_or_broadcast(slave)) return Unexpected{CodecError::bad_slave};
  if (pdu.empty() || pdu.size() > kMaxPduSize) return Unexpected{CodecError::bad_pdu};
  Bytes frame(pdu.size() + 1);
  frame[0] = slave;
  std::copy(pdu.begin(), pdu.end(), frame.begin() + 1);
  return finish(slave, std::move(frame));
}

Expected<Reply, CodecError> parse_reply(const Request& request,
                                        std::span<const std::uint8_t> frame) {
  if (frame.size() < 5) return Unexpected{CodecError::too_short};  // the shortest: an exception
  if (!crc_ok(frame)) return Unexpected{CodecError::crc_mismatch};
  if (frame[0] != request.slave) return Unexpected{CodecError::wrong_slave};
  return parse_reply_pdu(request, frame.subspan(1, frame.size() - 3));
}

Expected<Reply, CodecError> parse_reply_pdu(const Request& request,
                                            std::span<const std::uint8_t> pdu) {
  if (pdu.size() < 2) return Unexpected{CodecError::too_short};
  const std::uint8_t function = pdu[0];
  if ((function & ~kExceptionBit) != request.function)
    return Unexpected{CodecError::wrong_function};
  Reply reply{request.slave, request.function, std::nullopt, {}, Bytes(pdu.begin(), pdu.end())};
  if (function & kExceptionBit) {
    if (pdu.size() != 2) return Unexpected{CodecError::bad_length};
    reply.exception = pdu[1];
    return reply;
  }
  if (auto checked = check_data(request, pdu); !checked) return Unexpected{checked.error()};
  if (function == kReadHoldingRegisters || function == kReadInputRegisters)
    for (std::size_t at = 2; at + 2 <= pdu.size(); at += 2)
      reply.registers.push_back(get_u16(pdu, at));
  return reply;
}

Request readdressed(const Request& request, std::uint8_t slave) {
  Bytes frame(request.frame.begin(), request.frame.end() - 2);
  frame[0] = slave;
  return finish(slave, std::move(frame));
}

std::span<const std::uint8_t> request_pdu(const Request& request) {
  return std::span<const std::uint8_t>(request.frame).subspan(1, request.frame.size() - 3);
}

Bytes exception_pdu(std::uint8_t function, ExceptionCode code) {
  return Bytes{static_cast<std::uint8_t>(function | kExceptionBit),
               static_cast<std::uint8_t>(code)};
}

Bytes exception_frame(std::uint8_t slave, std::uint8_t function, ExceptionCode code) {
  Bytes frame{slave, static_cast<std::uint8_t>(function | kExceptionBit),
              static_cast<std::uint8_t>(code)};
  append_crc(frame);
  return frame;
}

}  // namespace tiltgate::modbus_rtu
