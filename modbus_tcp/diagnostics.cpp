#include "modbus_tcp/diagnostics.h"

#include "modbus_tcp/modbus_request.h"

namespace tiltgate {

namespace {

std::uint16_t diagnostic_word(std::span<const std::uint8_t> bytes, std::size_t at) {
  return std::uint16_t((bytes[at] << 8) | bytes[at + 1]);
}

void put_diagnostic_word(std::vector<std::uint8_t>& out, std::uint16_t value) {
  out.push_back(std::uint8_t(value >> 8));
  out.push_back(std::uint8_t(value & 0xFF));
}

}  // namespace

std::optional<ModbusException> check_diagnostics(std::span<const std::uint8_t> pdu,
                                                 ModbusRequest& request) {
  if (pdu.size() < 3) return ModbusException::illegal_value;
  const std::uint16_t sub_function = diagnostic_word(pdu, 1);
  request.diagnostic = sub_function;
  request.is_write = false;
  if (sub_function == diagnostic::return_query_data) return std::nullopt;
  if (sub_function != diagnostic::clear_counters && !returns_count(sub_function))
    return ModbusException::illegal_function;
  if (pdu.size() != 5 || diagnostic_word(pdu, 3) != 0x0000) return ModbusException::illegal_value;
  request.is_write = sub_function == diagnostic::clear_counters;
  return std::nullopt;
}

std::optional<ModbusException> check_comm_event_counter(std::span<const std::uint8_t> pdu) {
  if (pdu.size() != 1) return ModbusException::illegal_value;
  return std::nullopt;
}

std::vector<std::uint8_t> diagnostics_reply_data(const ModbusRequest& request,
                                                 std::span<const std::uint16_t> values) {
  std::vector<std::uint8_t> data;
  if (request.function == modbus_function::get_comm_event_counter) {
    if (values.size() < 2) return data;
    put_diagnostic_word(data, values[0]);
    put_diagnostic_word(data, values[1]);
    return data;
  }
  if (request.diagnostic == diagnostic::return_query_data ||
      request.diagnostic == diagnostic::clear_counters) {
    // Sub-function and data, as the request had them: after MBAP header and function code.
    const std::size_t from = mbap_header_size + 1;
    if (request.adu.size() >= from) data.assign(request.adu.begin() + from, request.adu.end());
    return data;
  }
  if (values.empty()) return data;
  put_diagnostic_word(data, request.diagnostic);
  put_diagnostic_word(data, values[0]);
  return data;
}

}  // namespace tiltgate
