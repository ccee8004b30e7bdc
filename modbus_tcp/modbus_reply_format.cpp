#include "modbus_tcp/modbus_reply_format.h"

#include "modbus_tcp/device_identification.h"
#include "modbus_tcp/diagnostics.h"
#include "modbus_tcp/modbus_request.h"

namespace tiltgate {

namespace {

bool is_bit_table(ModbusTable table) {
  return table == ModbusTable::coil || table == ModbusTable::discrete;
}

// The MBAP header (Implementation Guide section 3.1.3) and the function code; the length field
// is filled in by finish() once the PDU is complete.
void start(const ModbusRequest& request, std::uint8_t function, std::vector<std::uint8_t>& out) {
  out.clear();
  out.push_back(std::uint8_t(request.transaction_id >> 8));
  out.push_back(std::uint8_t(request.transaction_id & 0xFF));
  out.push_back(0x00);  // protocol id: Modbus
  out.push_back(0x00);
  out.push_back(0x00);  // length, below
  out.push_back(0x00);
  out.push_back(request.unit_id);
  out.push_back(function);
}

// The length field counts everything after itself: the unit id and the PDU.
void finish(std::vector<std::uint8_t>& out) {
  const std::size_t length = out.size() - 6;
  out[4] = std::uint8_t(length >> 8);
  out[5] = std::uint8_t(length & 0xFF);
}

void put16(std::vector<std::uint8_t>& out, std::uint16_t value) {
  out.push_back(std::uint8_t(value >> 8));
  out.push_back(std::uint8_t(value & 0xFF));
}

void format_exception(const ModbusRequest& request, ModbusException code,
                      std::vector<std::uint8_t>& out) {
  start(request, std::uint8_t(request.function | 0x80), out);
  out.push_back(std::uint8_t(code));
  finish(out);
}

// 01/02 (sections 6.1, 6.2): coil n is bit n % 8 of data byte n / 8, unused high bits 0.
void format_bits(const ModbusRequest& request, const std::vector<bool>& bits,
                 std::vector<std::uint8_t>& out) {
  start(request, request.function, out);
  const std::size_t bytes = (bits.size() + 7) / 8;
  out.push_back(std::uint8_t(bytes));
  const std::size_t data = out.size();
  out.resize(data + bytes, 0);
  for (std::size_t i = 0; i < bits.size(); ++i) {
    if (bits[i]) out[data + i / 8] |= std::uint8_t(1u << (i % 8));
  }
  finish(out);
}

// 03/04 (sections 6.3, 6.4).
void format_registers(const ModbusRequest& request, const std::vector<std::uint16_t>& registers,
                      std::vector<std::uint8_t>& out) {
  start(request, request.function, out);
  out.push_back(std::uint8_t(2 * registers.size()));
  // Sized once and written in place: up to 250 bytes, the hottest loop of a large read.
  const std::size_t data = out.size();
  out.resize(data + 2 * registers.size());
  std::uint8_t* at = out.data() + data;
  for (std::uint16_t value : registers) {
    *at++ = std::uint8_t(value >> 8);
    *at++ = std::uint8_t(value & 0xFF);
  }
  finish(out);
}

void format_device_identification(const ModbusRequest& request, const ModbusResponse& response,
                                  std::vector<std::uint8_t>& out) {
  auto pdu = encode_device_identification(response.device_objects, request.read_device_id_code,
                                          request.object_id);
  if (!pdu) return format_exception(request, pdu.error(), out);
  start(request, request.function, out);
  out.insert(out.end(), pdu->begin() + 1, pdu->end());  // the PDU after its function code
  finish(out);
}

// 08 and 11 (sections 6.8, 6.9): modbus_tcp/diagnostics.h.
void format_diagnostics(const ModbusRequest& request, const ModbusResponse& response,
                        std::vector<std::uint8_t>& out) {
  const std::vector<std::uint8_t> data = diagnostics_reply_data(request, response.registers);
  if (data.empty()) return format_exception(request, ModbusException::device_failure, out);
  start(request, request.function, out);
  out.insert(out.end(), data.begin(), data.end());
  finish(out);
}

}  // namespace

bool response_fits(const ModbusRequest& request, const ModbusResponse& response) {
  if (request.is_write) return true;
  const std::size_t values =
      is_bit_table(request.table) ? response.bits.size() : response.registers.size();
  return values == request.count;
}

void format_reply(const ModbusRequest& request, const ModbusResponse& response,
                  std::vector<std::uint8_t>& out) {
  if (response.exception) return format_exception(request, *response.exception, out);
  if (request.function == modbus_function::encapsulated_interface) {
    return format_device_identification(request, response, out);
  }
  if (request.function == modbus_function::diagnostics ||
      request.function == modbus_function::get_comm_event_counter) {
    return format_diagnostics(request, response, out);
  }
  if (!response_fits(request, response)) {
    return format_exception(request, ModbusException::device_failure, out);
  }
  switch (request.function) {
    case modbus_function::read_coils:
    case modbus_function::read_discrete_inputs:
      if (request.count > 2000) break;  // more than one PDU holds: not from parse_adu
      return format_bits(request, response.bits, out);
    case modbus_function::read_holding_registers:
    case modbus_function::read_input_registers:
      if (request.count > 125) break;
      return format_registers(request, response.registers, out);
    case modbus_function::write_single_coil:
      // The request echoed (section 6.5): 0xFF00 on, 0x0000 off.
      if (request.bits.size() != 1) break;
      start(request, request.function, out);
      put16(out, request.address);
      put16(out, request.bits[0] ? 0xFF00 : 0x0000);
      finish(out);
      return;
    case modbus_function::write_single_register:
      if (request.registers.size() != 1) break;  // section 6.6: the request echoed
      start(request, request.function, out);
      put16(out, request.address);
      put16(out, request.registers[0]);
      finish(out);
      return;
    case modbus_function::write_multiple_coils:
    case modbus_function::write_multiple_registers:
      start(request, request.function, out);  // sections 6.11, 6.12: address and quantity
      put16(out, request.address);
      put16(out, request.count);
      finish(out);
      return;
    default: break;
  }
  format_exception(request, ModbusException::device_failure, out);
}

std::vector<std::uint8_t> format_reply(const ModbusRequest& request,
                                       const ModbusResponse& response) {
  std::vector<std::uint8_t> reply;
  reply.reserve(max_adu_size);
  format_reply(request, response, reply);
  return reply;
}

}  // namespace tiltgate
