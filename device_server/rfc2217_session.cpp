#include "device_server/rfc2217_session.h"

#include <algorithm>
#include <array>
#include <utility>

namespace tiltgate {

namespace {

// RFC 2217 asks the client to say WILL COM-PORT-OPTION; binary mode keeps CR and 0x00 bytes
// as they are (RFC 856), and suppress-go-ahead is what every device server expects.
constexpr std::array<std::uint8_t, 3> kWeWill{telnet::kBinary, telnet::kSuppressGoAhead,
                                              telnet::kComPortOption};
constexpr std::array<std::uint8_t, 2> kWeDo{telnet::kBinary, telnet::kSuppressGoAhead};

bool among(std::span<const std::uint8_t> options, std::uint8_t option) {
  return std::find(options.begin(), options.end(), option) != options.end();
}

void append(std::vector<std::uint8_t>& out, const std::vector<std::uint8_t>& bytes) {
  out.insert(out.end(), bytes.begin(), bytes.end());
}

}  // namespace

std::vector<std::uint8_t> Rfc2217Session::offer() {
  std::vector<std::uint8_t> out;
  for (const std::uint8_t option : kWeWill) append(out, telnet::negotiation(telnet::kWill, option));
  for (const std::uint8_t option : kWeDo) append(out, telnet::negotiation(telnet::kDo, option));
  return out;
}

std::vector<std::uint8_t> Rfc2217Session::setting_requests() const {
  std::vector<std::uint8_t> out;
  for (const auto& payload : rfc2217::set_requests(setting_))
    append(out, telnet::subnegotiation(telnet::kComPortOption, payload));
  return out;
}

std::size_t Rfc2217Session::take(std::span<std::uint8_t> chunk) {
  const std::size_t data = reader_.take(chunk, commands_);
  for (const telnet::Command& command : commands_) handle(command);
  commands_.clear();
  return data;
}

void Rfc2217Session::handle(const telnet::Command& command) {
  if (command.option == telnet::kComPortOption) {
    if (command.verb == telnet::kDo) agreed_ = true;
    if (command.verb == telnet::kDont) option_refused_ = true;
    // Answers to the requests; notifications (modem or line state) are read past.
    if (command.verb == telnet::kSb) {
      if (const auto answer = rfc2217::read_answer(command.payload)) acks_.take(*answer);
    }
  }
  std::uint8_t reply = 0;
  if (command.verb == telnet::kDo && !among(kWeWill, command.option)) reply = telnet::kWont;
  if (command.verb == telnet::kWill && !among(kWeDo, command.option)) reply = telnet::kDont;
  if (reply == 0 || among(refused_options_, command.option)) return;
  refused_options_.push_back(command.option);
  append(replies_, telnet::negotiation(reply, command.option));
}

std::vector<std::uint8_t> Rfc2217Session::take_replies() { return std::exchange(replies_, {}); }

std::optional<std::string> Rfc2217Session::refusal() const {
  if (option_refused_)
    return "the server refused RFC 2217's COM-PORT-OPTION (is its port in RFC 2217 mode?)";
  return acks_.refused();
}

std::span<const std::uint8_t> Rfc2217Session::escaped(std::span<const std::uint8_t> data) {
  escaped_.clear();
  telnet::escape(data, escaped_);
  return escaped_;
}

}  // namespace tiltgate
