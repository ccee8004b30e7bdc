#include "modbus_rtu/adu_framing.h"

#include <chrono>

#include "modbus_rtu/mbap_reply_framer.h"

namespace tiltgate::modbus_rtu {

Adu adu_of(std::string_view protocol) {
  return protocol == kModbusTcpProtocol ? Adu::mbap : Adu::rtu;
}

std::uint16_t fresh_transaction_id() {
  const auto now = std::chrono::steady_clock::now().time_since_epoch();
  const auto us = std::chrono::duration_cast<std::chrono::microseconds>(now).count();
  return static_cast<std::uint16_t>(us);
}

std::unique_ptr<ModbusReplyFramer> AduFraming::framer(Request request) {
  if (adu_ == Adu::rtu) return std::make_unique<RtuReplyFramer>(std::move(request));
  return std::make_unique<MbapReplyFramer>(std::move(request), next_transaction_++);
}

}  // namespace tiltgate::modbus_rtu
