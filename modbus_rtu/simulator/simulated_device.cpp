#include "modbus_rtu/simulator/simulated_device.h"

#include <algorithm>

#include "modbus_rtu/big_endian.h"
#include "modbus_rtu/crc.h"

namespace tiltgate::modbus_rtu {
namespace {

bool in_bank(std::size_t address, std::size_t count, std::size_t bank_size) {
  return address + count <= bank_size;
}

}  // namespace

SimulatedDevice::SimulatedDevice(std::uint8_t slave, std::size_t holding_count,
                                 std::size_t input_count)
    : slave_(slave), holding_(holding_count, 0), input_(input_count, 0) {}

std::optional<DeviceReply> SimulatedDevice::respond(std::span<const std::uint8_t> request) {
  if (request.size() < 4) return std::nullopt;
  const std::uint8_t address = request[0];
  const bool broadcast = address == kBroadcastAddress;
  if (address != slave_ && !broadcast) return std::nullopt;
  ++requests_handled_;
  const std::uint8_t function = request[1];
  const bool is_write = function == kWriteSingleRegister || function == kWriteMultipleRegisters;
  if (broadcast && !is_write) return std::nullopt;  // Serial Line 2.2: broadcasts are writes
  const Bytes pdu = answer(request.subspan(1, request.size() - 3));
  if (broadcast) return std::nullopt;
  if (faults_.silent > 0) {
    --faults_.silent;
    return std::nullopt;
  }
  DeviceReply reply{Bytes(pdu.size() + 1), std::chrono::milliseconds{0}};
  reply.frame[0] = slave_;
  std::copy(pdu.begin(), pdu.end(), reply.frame.begin() + 1);
  append_crc(reply.frame);
  if (faults_.corrupt_crc > 0) {
    --faults_.corrupt_crc;
    reply.frame[reply.frame.size() - 2] ^= 0xFF;
  }
  if (faults_.late > 0) {
    --faults_.late;
    reply.delay = faults_.late_by;
  }
  return reply;
}

Bytes SimulatedDevice::answer(std::span<const std::uint8_t> pdu) {
  const std::uint8_t function = pdu[0];
  switch (function) {
    case kReadHoldingRegisters: return answer_read(pdu, holding_);
    case kReadInputRegisters: return answer_read(pdu, input_);
    case kWriteSingleRegister: return answer_write_single(pdu);
    case kWriteMultipleRegisters: return answer_write_multiple(pdu);
    case kReportServerId: return answer_report_server_id(identification_, pdu);
    case kEncapsulatedInterface: return answer_device_identification(identification_, pdu);
    default: return exception_pdu(function, ExceptionCode::illegal_function);
  }
}

Bytes SimulatedDevice::answer_read(std::span<const std::uint8_t> pdu,
                                   const std::vector<std::uint16_t>& bank) {
  const std::uint8_t function = pdu[0];
  if (pdu.size() != 5) return exception_pdu(function, ExceptionCode::illegal_data_value);
  const std::uint16_t address = get_u16(pdu, 1);
  const std::uint16_t count = get_u16(pdu, 3);
  if (count < 1 || count > kMaxReadCount)
    return exception_pdu(function, ExceptionCode::illegal_data_value);
  if (!in_bank(address, count, bank.size()))
    return exception_pdu(function, ExceptionCode::illegal_data_address);
  Bytes reply{function, static_cast<std::uint8_t>(2 * count)};
  for (std::size_t i = 0; i < count; ++i) put_u16(reply, bank[address + i]);
  return reply;
}

Bytes SimulatedDevice::answer_write_single(std::span<const std::uint8_t> pdu) {
  if (pdu.size() != 5) return exception_pdu(kWriteSingleRegister, ExceptionCode::illegal_data_value);
  const std::uint16_t address = get_u16(pdu, 1);
  const std::uint16_t value = get_u16(pdu, 3);
  if (!in_bank(address, 1, holding_.size()))
    return exception_pdu(kWriteSingleRegister, ExceptionCode::illegal_data_address);
  if (!write_allowed(address, std::span(&value, 1)))
    return exception_pdu(kWriteSingleRegister, ExceptionCode::illegal_data_value);
  holding_[address] = value;
  return Bytes(pdu.begin(), pdu.end());  // the request echoed
}

Bytes SimulatedDevice::answer_write_multiple(std::span<const std::uint8_t> pdu) {
  constexpr std::uint8_t f = kWriteMultipleRegisters;
  if (pdu.size() < 6) return exception_pdu(f, ExceptionCode::illegal_data_value);
  const std::uint16_t address = get_u16(pdu, 1);
  const std::uint16_t count = get_u16(pdu, 3);
  const std::uint8_t byte_count = pdu[5];
  if (count < 1 || count > kMaxWriteCount || byte_count != 2 * count ||
      pdu.size() != 6u + byte_count)
    return exception_pdu(f, ExceptionCode::illegal_data_value);
  if (!in_bank(address, count, holding_.size()))
    return exception_pdu(f, ExceptionCode::illegal_data_address);
  std::vector<std::uint16_t> values;
  for (std::size_t i = 0; i < count; ++i) values.push_back(get_u16(pdu, 6 + 2 * i));
  if (!write_allowed(address, values)) return exception_pdu(f, ExceptionCode::illegal_data_value);
  for (std::size_t i = 0; i < count; ++i) holding_[address + i] = values[i];
  return Bytes(pdu.begin(), pdu.begin() + 5);  // function, address, count
}

bool SimulatedDevice::write_allowed(std::uint16_t address,
                                    std::span<const std::uint16_t> values) const {
  if (!write_check_) return true;
  for (std::size_t i = 0; i < values.size(); ++i)
    if (!write_check_(static_cast<std::uint16_t>(address + i), values[i])) return false;
  return true;
}

}  // namespace tiltgate::modbus_rtu
