#include "spectron/raw.h"

#include <fmt/format.h>

#include "driver/hex.h"
#include "spectron/ascii_codec.h"
#include "spectron/assumptions.h"
#include "spectron/nine_bit_codec.h"
#include "spectron/reply_framers.h"

namespace tiltgate::spectron {

namespace {

// A command byte each; as much data as a request the module reads can carry: a Modbus-ASCII
// frame (':', address, command, two hex digits a byte, LRC, CR LF) or a 9-bit line (the command
// character and the argument characters) of at most 64 characters (spectron/assumptions.h).
constexpr RawLimits kAsciiLimits{"command code", 0, 0xFF, (kMaxFrameLength - 9) / 2};
constexpr RawLimits kNineBitLimits{"command code", 0, 0xFF, kMaxLineLength - 1};

class AsciiExchange final : public RawExchange {
 public:
  explicit AsciiExchange(AsciiFrame request)
      : RawExchange(encode(request)), framer_(std::move(request)) {}

  // The module refuses by not answering (spectron/assumptions.h): every reply is an answer.
  RawReply decode() const override {
    const AsciiFrame& reply = *framer_.reply();
    const char* name = ascii_command_name(reply.command);
    std::string text = fmt::format("reply:    command 0x{:02X}{}, {} data byte(s): {}", reply.command,
                                   name ? fmt::format(" ({})", name) : "", reply.data.size(),
                                   hex_bytes(reply.data));
    if (reply.data.empty()) text += "\n          (an acknowledgement)";
    if (const auto word = word_at(reply, 0); word && reply.data.size() == 2) {
      text += fmt::format("\nword:     {} (signed {})", *word, std::int16_t(*word));
      if (reply.command == std::uint8_t(AsciiCommand::revision))
        text += fmt::format("\nrevision: {}", revision_text(*word));
    }
    return {false, text};
  }

 private:
  ReplyFramer& framer() override { return framer_; }

  AsciiReplyFramer framer_;
};

class NineBitExchange final : public RawExchange {
 public:
  explicit NineBitExchange(const NineBitRequest& request)
      : RawExchange(wire_bytes(request), kNineBitAddressBytes) {}

  RawReply decode() const override {
    return {false, fmt::format("reply:    \"{}\"", *framer_.reply())};
  }

 private:
  ReplyFramer& framer() override { return framer_; }

  NineBitReplyFramer framer_;
};

}  // namespace

Expected<std::unique_ptr<RawExchange>, std::string> make_raw_exchange(const RawSetup& setup) {
  const bool nine_bit = setup.protocol == "spectron-9bit";
  if (auto checked = check_raw_setup(setup, nine_bit ? kNineBitLimits : kAsciiLimits); !checked)
    return Unexpected{checked.error()};
  if (nine_bit) {
    NineBitRequest request;
    request.address = std::uint8_t(setup.address);
    request.body.push_back(std::uint8_t(setup.function));
    for (std::uint8_t byte : setup.data) request.body.push_back(byte);
    request.body.push_back('\r');
    request.body.push_back('\n');
    return std::unique_ptr<RawExchange>(std::make_unique<NineBitExchange>(request));
  }
  AsciiFrame request;
  request.address = std::uint8_t(setup.address);
  request.command = std::uint8_t(setup.function);
  request.data = setup.data;
  return std::unique_ptr<RawExchange>(std::make_unique<AsciiExchange>(std::move(request)));
}

}  // namespace tiltgate::spectron
