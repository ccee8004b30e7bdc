// The client's side of one RFC 2217 conversation, as a pure state machine: what to send on
// connect (the Telnet options asked for), the COM-PORT-OPTION requests that set the far port,
// and what the server's bytes mean (data for the line, agreement, confirmations, refusals).
// NetworkPort (device_server/network_port.h) moves its bytes; a new connection is a new session.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "device_server/com_port_option.h"
#include "device_server/telnet_codec.h"

namespace tiltgate {

class Rfc2217Session {
 public:
  explicit Rfc2217Session(rfc2217::PortSetting setting) : setting_(setting), acks_(setting) {}

  // At connect: WILL BINARY, SUPPRESS-GO-AHEAD and COM-PORT-OPTION; DO BINARY and
  // SUPPRESS-GO-AHEAD.
  static std::vector<std::uint8_t> offer();
  // Once agreed(): the far port's rate, data size, parity, stop bits and no flow control.
  std::vector<std::uint8_t> setting_requests() const;

  // Takes the server's commands out of `chunk` in place and returns how many data bytes are
  // left at its front; refusals of options it offers that were not asked for are queued.
  std::size_t take(std::span<std::uint8_t> chunk);
  // What the session owes the server now (WONT/DONT, once per option); empties the queue.
  std::vector<std::uint8_t> take_replies();

  // The server said DO COM-PORT-OPTION.
  bool agreed() const { return agreed_; }
  // Rate, data size, parity and stop bits all confirmed as asked.
  bool confirmed() const { return acks_.complete(); }
  // Why the port cannot be used as asked: the option refused, or a setting answered otherwise.
  std::optional<std::string> refusal() const;
  // What is still unconfirmed ("baud rate, parity").
  std::string missing() const { return acks_.missing(); }

  // `data` as it goes on the connection (0xFF doubled), valid until the next call.
  std::span<const std::uint8_t> escaped(std::span<const std::uint8_t> data);

 private:
  void handle(const telnet::Command& command);

  rfc2217::PortSetting setting_;
  rfc2217::Acknowledgements acks_;
  telnet::Reader reader_;
  std::vector<telnet::Command> commands_;
  std::vector<std::uint8_t> refused_options_;  // answered WONT/DONT already
  std::vector<std::uint8_t> replies_;
  std::vector<std::uint8_t> escaped_;
  bool agreed_ = false;
  bool option_refused_ = false;
};

}  // namespace tiltgate
