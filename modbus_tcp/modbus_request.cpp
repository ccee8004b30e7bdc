#include "modbus_tcp/modbus_request.h"

#include <algorithm>
#include <cstring>
#include <optional>

#include "modbus_tcp/device_identification.h"
#include "modbus_tcp/diagnostics.h"

namespace tiltgate {

namespace {

// The MBAP length field counts the unit id and the PDU: at least unit id + function code, at
// most unit id + the 253-byte PDU (Implementation Guide section 3.1.3; libmodbus uses 260 as
// its TCP maximum ADU, which is the same limit).
constexpr std::uint16_t min_mbap_length = 2;
constexpr std::uint16_t max_mbap_length = 254;
// Addresses are 16 bits: a range may end at 0xFFFF but not run past it.
constexpr std::uint32_t address_space = 0x10000;

std::uint16_t be16(std::span<const std::uint8_t> bytes, std::size_t at) {
  return std::uint16_t((bytes[at] << 8) | bytes[at + 1]);
}

struct FunctionRule;
using PduCheck = std::optional<ModbusException> (*)(const FunctionRule& rule,
                                                    std::span<const std::uint8_t> pdu,
                                                    ModbusRequest& request);

// One row per function the server answers. Supporting a new function is one more row with its
// own check, plus its reply in the encoder.
struct FunctionRule {
  std::uint8_t function;
  ModbusTable table;
  bool is_write;
  std::uint16_t max_count;  // the quantity limit of Application Protocol section 6.x
  PduCheck check;
};

bool range_fits(std::uint16_t address, std::uint16_t count) {
  return std::uint32_t(address) + count <= address_space;
}

// 01-04: function, address, quantity (section 6.1-6.4). The spec checks the quantity first
// (exception 03), then the address range (exception 02).
std::optional<ModbusException> check_read(const FunctionRule& rule,
                                          std::span<const std::uint8_t> pdu,
                                          ModbusRequest& request) {
  if (pdu.size() != 5) return ModbusException::illegal_value;
  request.address = be16(pdu, 1);
  request.count = be16(pdu, 3);
  if (request.count < 1 || request.count > rule.max_count) return ModbusException::illegal_value;
  if (!range_fits(request.address, request.count)) return ModbusException::illegal_address;
  return std::nullopt;
}

// 05: the output value must be 0xFF00 (on) or 0x0000 (off), section 6.5.
std::optional<ModbusException> check_write_single_coil(const FunctionRule&,
                                                       std::span<const std::uint8_t> pdu,
                                                       ModbusRequest& request) {
  if (pdu.size() != 5) return ModbusException::illegal_value;
  const std::uint16_t value = be16(pdu, 3);
  if (value != 0x0000 && value != 0xFF00) return ModbusException::illegal_value;
  request.address = be16(pdu, 1);
  request.count = 1;
  request.bits = {value == 0xFF00};
  return std::nullopt;
}

// 06: any 16-bit value, section 6.6.
std::optional<ModbusException> check_write_single_register(const FunctionRule&,
                                                           std::span<const std::uint8_t> pdu,
                                                           ModbusRequest& request) {
  if (pdu.size() != 5) return ModbusException::illegal_value;
  request.address = be16(pdu, 1);
  request.count = 1;
  request.registers = {be16(pdu, 3)};
  return std::nullopt;
}

// 15 and 16: function, address, quantity, byte count, values (sections 6.11, 6.12). The
// quantity, the byte count and the PDU length must all agree, or the request is 03.
std::optional<ModbusException> check_write_multiple(const FunctionRule& rule,
                                                    std::span<const std::uint8_t> pdu,
                                                    ModbusRequest& request,
                                                    std::size_t bytes_for_count) {
  if (pdu.size() < 6) return ModbusException::illegal_value;
  request.address = be16(pdu, 1);
  request.count = be16(pdu, 3);
  const std::size_t byte_count = pdu[5];
  if (request.count < 1 || request.count > rule.max_count) return ModbusException::illegal_value;
  if (byte_count != bytes_for_count || pdu.size() != 6 + byte_count) {
    return ModbusException::illegal_value;
  }
  if (!range_fits(request.address, request.count)) return ModbusException::illegal_address;
  return std::nullopt;
}

std::optional<ModbusException> check_write_multiple_coils(const FunctionRule& rule,
                                                          std::span<const std::uint8_t> pdu,
                                                          ModbusRequest& request) {
  const std::size_t count = pdu.size() >= 5 ? be16(pdu, 3) : 0;
  if (auto bad = check_write_multiple(rule, pdu, request, (count + 7) / 8)) return bad;
  // Coil n is bit n % 8 of data byte n / 8, least significant bit first (section 6.11).
  request.bits.resize(request.count);
  for (std::size_t i = 0; i < request.count; ++i) {
    request.bits[i] = (pdu[6 + i / 8] >> (i % 8)) & 1;
  }
  return std::nullopt;
}

std::optional<ModbusException> check_write_multiple_registers(const FunctionRule& rule,
                                                              std::span<const std::uint8_t> pdu,
                                                              ModbusRequest& request) {
  const std::size_t count = pdu.size() >= 5 ? be16(pdu, 3) : 0;
  if (auto bad = check_write_multiple(rule, pdu, request, 2 * count)) return bad;
  request.registers.resize(request.count);
  for (std::size_t i = 0; i < request.count; ++i) request.registers[i] = be16(pdu, 6 + 2 * i);
  return std::nullopt;
}

// 43 / 14 Read Device Identification (section 6.21): function, MEI type, Read Device ID code,
// object id, nothing more. Another MEI type is a function the gateway does not serve (01, as
// the section's state diagram has it for an unsupported MEI type); a missing or extra byte or
// a Read Device ID code other than 1..4 is 03. Whether the object exists is the unit's
// business (02 for individual access, a restart for streams).
std::optional<ModbusException> check_read_device_identification(
    const FunctionRule&, std::span<const std::uint8_t> pdu, ModbusRequest& request) {
  if (pdu.size() < 2) return ModbusException::illegal_value;
  if (pdu[1] != mei_read_device_identification) return ModbusException::illegal_function;
  if (pdu.size() != 4) return ModbusException::illegal_value;
  if (pdu[2] < read_device_id::basic_stream || pdu[2] > read_device_id::one_object) {
    return ModbusException::illegal_value;
  }
  request.read_device_id_code = pdu[2];
  request.object_id = pdu[3];
  return std::nullopt;
}

// 08 and 11 (sections 6.8, 6.9): modbus_tcp/diagnostics.h. 08's check says which
// sub-function is a write (0x000A).
std::optional<ModbusException> check_diagnostics_rule(const FunctionRule&,
                                                      std::span<const std::uint8_t> pdu,
                                                      ModbusRequest& request) {
  return check_diagnostics(pdu, request);
}

std::optional<ModbusException> check_comm_event_counter_rule(const FunctionRule&,
                                                             std::span<const std::uint8_t> pdu,
                                                             ModbusRequest&) {
  return check_comm_event_counter(pdu);
}

constexpr FunctionRule function_rules[] = {
    {modbus_function::read_coils, ModbusTable::coil, false, 2000, check_read},
    {modbus_function::read_discrete_inputs, ModbusTable::discrete, false, 2000, check_read},
    {modbus_function::read_holding_registers, ModbusTable::holding, false, 125, check_read},
    {modbus_function::read_input_registers, ModbusTable::input, false, 125, check_read},
    {modbus_function::write_single_coil, ModbusTable::coil, true, 1, check_write_single_coil},
    {modbus_function::write_single_register, ModbusTable::holding, true, 1,
     check_write_single_register},
    {modbus_function::write_multiple_coils, ModbusTable::coil, true, 1968,
     check_write_multiple_coils},
    {modbus_function::write_multiple_registers, ModbusTable::holding, true, 123,
     check_write_multiple_registers},
    // Table and count unused: the reply is built from the unit's identification objects.
    {modbus_function::encapsulated_interface, ModbusTable::holding, false, 0,
     check_read_device_identification},
    // Table and count unused: the reply is the unit's counts (gateway/unit_diagnostics.h).
    {modbus_function::diagnostics, ModbusTable::holding, false, 0, check_diagnostics_rule},
    {modbus_function::get_comm_event_counter, ModbusTable::holding, false, 0,
     check_comm_event_counter_rule},
};

const FunctionRule* rule_for(std::uint8_t function) {
  for (const FunctionRule& rule : function_rules) {
    if (rule.function == function) return &rule;
  }
  return nullptr;
}

RejectedRequest reject(std::span<const std::uint8_t> adu, ModbusException code) {
  return RejectedRequest{code, exception_reply(adu, code)};
}

}  // namespace

const char* to_string(FramingError error) {
  switch (error) {
    case FramingError::protocol_id: return "MBAP protocol id is not 0";
    case FramingError::length: return "MBAP length outside 2..254";
  }
  return "bad MBAP header";
}

Expected<std::size_t, FramingError> adu_size(
    std::span<const std::uint8_t, mbap_header_size> header) {
  if (be16(header, 2) != 0) return Unexpected(FramingError::protocol_id);
  const std::uint16_t length = be16(header, 4);
  if (length < min_mbap_length || length > max_mbap_length) {
    return Unexpected(FramingError::length);
  }
  // The length field counts everything after itself: the unit id and the PDU.
  return std::size_t{6} + length;
}

std::optional<AduProblem> parse_adu_into(std::span<const std::uint8_t> adu,
                                         ModbusRequest& request) {
  if (adu.size() < mbap_header_size) return FramingError::length;
  auto size = adu_size(adu.first<mbap_header_size>());
  if (!size) return size.error();
  if (*size != adu.size()) return FramingError::length;

  // Every field set again (the object is reused), its vectors cleared within their capacity.
  request.transaction_id = be16(adu, 0);
  request.unit_id = adu[6];
  request.function = adu[7];
  request.address = 0;
  request.count = 0;
  request.registers.clear();
  request.bits.clear();
  request.read_device_id_code = 0;
  request.object_id = 0;
  request.diagnostic = 0;
  const FunctionRule* rule = rule_for(request.function);
  // Unknown functions (07, 17, 23, ...) never reach the handler or the reply formatter.
  if (rule == nullptr) return reject(adu, ModbusException::illegal_function);
  request.table = rule->table;
  request.is_write = rule->is_write;
  if (auto bad = rule->check(*rule, adu.subspan(mbap_header_size), request)) {
    return reject(adu, *bad);
  }
  request.adu.assign(adu.begin(), adu.end());
  return std::nullopt;
}

ParsedAdu parse_adu(std::span<const std::uint8_t> adu) {
  ModbusRequest request;
  if (auto problem = parse_adu_into(adu, request)) {
    if (auto* rejected = std::get_if<RejectedRequest>(&*problem)) return std::move(*rejected);
    return std::get<FramingError>(*problem);
  }
  return request;
}

std::vector<std::uint8_t> exception_reply(std::span<const std::uint8_t> adu,
                                          ModbusException code) {
  // Same transaction and unit, protocol 0, length 3 (unit id, function | 0x80, code);
  // Application Protocol section 7.
  return {adu[0], adu[1], 0x00, 0x00, 0x00, 0x03, adu[6], std::uint8_t(adu[7] | 0x80),
          std::uint8_t(code)};
}

std::vector<std::uint8_t> relayed_reply(std::span<const std::uint8_t> adu,
                                        std::span<const std::uint8_t> pdu) {
  // The length field counts the unit id and the PDU (Implementation Guide section 3.1.3).
  const std::size_t length = 1 + pdu.size();
  std::vector<std::uint8_t> reply(mbap_header_size + pdu.size());
  std::copy(adu.begin(), adu.begin() + 4, reply.begin());  // transaction and protocol id
  reply[4] = std::uint8_t(length >> 8);
  reply[5] = std::uint8_t(length & 0xFF);
  reply[6] = adu[6];
  std::copy(pdu.begin(), pdu.end(), reply.begin() + mbap_header_size);
  return reply;
}

ModbusFrameAssembler::Next ModbusFrameAssembler::next() const {
  if (buffered() < mbap_header_size) return NeedMore{};
  auto size = adu_size(std::span(buffer_).subspan(start_).first<mbap_header_size>());
  if (!size) return size.error();
  if (buffered() < *size) return NeedMore{};
  return std::span<const std::uint8_t>(buffer_.data() + start_, *size);
}

void ModbusFrameAssembler::pop() {
  auto front = next();
  auto* adu = std::get_if<std::span<const std::uint8_t>>(&front);
  if (adu == nullptr) return;
  start_ += adu->size();
  if (start_ == end_) start_ = end_ = 0;
}

std::span<std::uint8_t> ModbusFrameAssembler::space() {
  // What is left of the stream moves to the front once there is less room than a frame.
  if (buffer_.size() - end_ < max_adu_size) {
    std::memmove(buffer_.data(), buffer_.data() + start_, buffered());
    end_ -= start_;
    start_ = 0;
  }
  return std::span(buffer_).subspan(end_);
}

}  // namespace tiltgate
