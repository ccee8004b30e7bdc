#include "spectron/raw.h"

#include <fmt/format.h>

#include "driver/hex.h"
#include "spectron/ascii_codec.h"
#include "spectron/nine_bit_codec.h"
#include "spectron/reply_framers.h"

namespace tiltgate::spectron {

namespace {

class AsciiExchange final : public RawExchange {
 public:
  explicit AsciiExchange(AsciiFrame request) : request_(request), framer_(std::move(request)) {}

  LineRequest request() override {
    LineRequest line_request;
    line_request.bytes = encode(request_);
    line_request.framer = &framer_;
    return line_request;
  }

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
  AsciiFrame request_;
  AsciiReplyFramer framer_;
};

class NineBitExchange final : public RawExchange {
 public:
  explicit NineBitExchange(NineBitRequest request) : request_(std::move(request)) {}

  LineRequest request() override {
    LineRequest line_request;
    line_request.bytes = wire_bytes(request_);
    line_request.address_bytes = kNineBitAddressBytes;
    line_request.framer = &framer_;
    return line_request;
  }

  RawReply decode() const override {
    return {false, fmt::format("reply:    \"{}\"", *framer_.reply())};
  }

 private:
  NineBitRequest request_;
  NineBitReplyFramer framer_;
};

}  // namespace

Expected<std::unique_ptr<RawExchange>, std::string> make_raw_exchange(const RawSetup& setup) {
  if (setup.function < 0 || setup.function > 0xFF)
    return Unexpected{fmt::format("--function: {} is not a command code 0..255", setup.function)};
  if (setup.protocol == "spectron-9bit") {
    NineBitRequest request;
    request.address = std::uint8_t(setup.address);
    request.body.push_back(std::uint8_t(setup.function));
    request.body.insert(request.body.end(), setup.data.begin(), setup.data.end());
    request.body.push_back('\r');
    request.body.push_back('\n');
    return std::unique_ptr<RawExchange>(std::make_unique<NineBitExchange>(std::move(request)));
  }
  AsciiFrame request;
  request.address = std::uint8_t(setup.address);
  request.command = std::uint8_t(setup.function);
  request.data = setup.data;
  return std::unique_ptr<RawExchange>(std::make_unique<AsciiExchange>(std::move(request)));
}

}  // namespace tiltgate::spectron
