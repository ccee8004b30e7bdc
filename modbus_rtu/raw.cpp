#include "modbus_rtu/raw.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "driver/hex.h"
#include "modbus_rtu/codec.h"
#include "modbus_rtu/reply_framer.h"

namespace tiltgate::modbus_rtu {

namespace {

// A function code (the exception bit clear) and the rest of a PDU of at most 253 bytes.
constexpr RawLimits kLimits{"Modbus function code", 1, 127, kMaxPduSize - 1};

class Exchange final : public RawExchange {
 public:
  explicit Exchange(Request request) : RawExchange(request.frame), framer_(std::move(request)) {}

  RawReply decode() const override {
    const Expected<Reply, CodecError>& reply = *framer_.reply();
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
  ReplyFramer& framer() override { return framer_; }

  RtuReplyFramer framer_;
};

}  // namespace

Expected<std::unique_ptr<RawExchange>, std::string> make_raw_exchange(const RawSetup& setup) {
  if (auto checked = check_raw_setup(setup, kLimits); !checked) return Unexpected{checked.error()};
  Bytes pdu{std::uint8_t(setup.function)};
  pdu.insert(pdu.end(), setup.data.begin(), setup.data.end());
  auto request = raw_request(std::uint8_t(setup.address), pdu);
  if (!request) return Unexpected{fmt::format("--data: {}", to_string(request.error()))};
  return std::unique_ptr<RawExchange>(std::make_unique<Exchange>(std::move(*request)));
}

}  // namespace tiltgate::modbus_rtu
