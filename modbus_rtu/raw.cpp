#include "modbus_rtu/raw.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "driver/hex.h"
#include "modbus_rtu/adu_framing.h"
#include "modbus_rtu/codec.h"

namespace tiltgate::modbus_rtu {

namespace {

// A function code (the exception bit clear) and the rest of a PDU of at most 253 bytes.
constexpr RawLimits kLimits{"Modbus function code", 1, 127, kMaxPduSize - 1};

class Exchange final : public RawExchange {
 public:
  explicit Exchange(std::unique_ptr<ModbusReplyFramer> framer)
      : RawExchange(framer->request_bytes()), framer_(std::move(framer)) {}

  RawReply decode() const override {
    const Expected<Reply, CodecError>& reply = *framer_->reply();
    if (!reply)
      return {true, fmt::format("reply:    not a valid reply to the request: {}", to_string(reply.error()))};
    if (reply->exception)
      return {true, fmt::format("reply:    exception 0x{:02X} ({})", *reply->exception,
                                exception_name(*reply->exception))};
    std::string text = fmt::format("reply:    function 0x{:02X}, PDU {}", reply->function,
                                   hex_bytes(reply->pdu));
    if (!reply->registers.empty())
      text += fmt::format("\nregisters: {}", fmt::join(reply->registers, " "));
    return {false, text};
  }

 private:
  ReplyFramer& framer() override { return *framer_; }

  std::unique_ptr<ModbusReplyFramer> framer_;
};

}  // namespace

Expected<std::unique_ptr<RawExchange>, std::string> make_raw_exchange(const RawSetup& setup) {
  if (auto checked = check_raw_setup(setup, kLimits); !checked) return Unexpected{checked.error()};
  Bytes pdu{std::uint8_t(setup.function)};
  pdu.insert(pdu.end(), setup.data.begin(), setup.data.end());
  auto framer = AduFraming(adu_of(setup.protocol))
                    .exchange(std::uint8_t(setup.address),
                              [&pdu](std::uint8_t slave) { return raw_request(slave, pdu); });
  if (!framer) return Unexpected{fmt::format("--data: {}", to_string(framer.error()))};
  return std::unique_ptr<RawExchange>(std::make_unique<Exchange>(std::move(*framer)));
}

}  // namespace tiltgate::modbus_rtu
