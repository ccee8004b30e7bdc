#include "rieker/raw.h"

#include <fmt/format.h>

#include "driver/hex.h"
#include "rieker/codec.h"
#include "rieker/reply_framer.h"

namespace tiltgate::rieker {

namespace {

std::string function_text(std::uint16_t function) {
  const char* name = function_name(function);
  return name ? fmt::format("{} ({})", function, name) : std::to_string(function);
}

// What the typed parsers make of a reply to a function they know.
std::string typed_value(const Frame& request, const Frame& reply) {
  switch (Function(request.function)) {
    case Function::get_serial:
      if (auto serial = parse_serial_reply(reply)) return "serial:   " + *serial;
      break;
    case Function::get_firmware:
      if (auto firmware = parse_firmware_reply(reply)) return "firmware: " + *firmware;
      break;
    case Function::get_lock_level:
      if (auto level = parse_lock_level_reply(reply)) return fmt::format("lock level: {}", int(*level));
      break;
    case Function::get_address:
      if (auto address = parse_address_reply(reply)) return fmt::format("address:  {}", *address);
      break;
    case Function::get_angle: {
      if (request.data.size() != 1) break;
      const auto angles = parse_angle_reply(reply, AngleType(request.data[0]));
      if (!angles) break;
      std::string text;
      if (angles->x) text += fmt::format("angle x:  {:.3f} deg", *angles->x);
      if (angles->y) text += fmt::format("{}angle y:  {:.3f} deg", text.empty() ? "" : "\n", *angles->y);
      return text;
    }
    default: break;
  }
  return "";
}

// The command code and DATA fit the frame's FUNCT word and one-byte DL.
constexpr RawLimits kLimits{"command code", 0, 0xFFFF, kMaxDataSize};

class Exchange final : public RawExchange {
 public:
  explicit Exchange(Frame request)
      : RawExchange(encode(request)), request_(std::move(request)), framer_(request_) {}

  RawReply decode() const override {
    const Frame& reply = *framer_.reply();
    if (reply.function == std::uint16_t(Function::ack)) return {false, "reply:    ACK"};
    if (reply.function == std::uint16_t(Function::nak)) {
      const std::uint8_t code = reply.data.size() == 1 ? reply.data[0] : 0xFF;
      return {true, fmt::format("reply:    NAK {} ({})", code, nak_name(code))};
    }
    std::string text = fmt::format("reply:    function {}, {} data byte(s): {}",
                                   function_text(reply.function), reply.data.size(),
                                   hex_bytes(reply.data));
    if (const std::string value = typed_value(request_, reply); !value.empty())
      text += "\n" + value;
    return {false, text};
  }

 private:
  ReplyFramer& framer() override { return framer_; }

  Frame request_;
  RiekerReplyFramer framer_;
};

}  // namespace

Expected<std::unique_ptr<RawExchange>, std::string> make_raw_exchange(const RawSetup& setup) {
  if (auto checked = check_raw_setup(setup, kLimits); !checked) return Unexpected{checked.error()};
  Frame request;
  request.dest = std::uint16_t(setup.address);
  request.src = std::uint16_t(setup.master_address);
  request.function = std::uint16_t(setup.function);
  request.data = setup.data;
  return std::unique_ptr<RawExchange>(std::make_unique<Exchange>(std::move(request)));
}

}  // namespace tiltgate::rieker
