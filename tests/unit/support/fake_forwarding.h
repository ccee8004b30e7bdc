// A fake protocol that can forward Modbus PDUs, for testing pass-through in the gateway core
// without a real one: a PDU goes out as slave + PDU, and any bytes that come back are the
// whole reply, the PDU after its first byte.
#pragma once

#include <memory>
#include <span>
#include <string>
#include <vector>

#include "driver/forwarded_exchange.h"

namespace tiltgate::test {

// Takes whatever arrives as the whole reply: the fake protocol's framer, and a command's that
// takes its sensor's reply.
class AnyReply final : public ReplyFramer {
 public:
  void reset() override { received.clear(); }
  bool feed(std::span<const std::uint8_t> bytes) override {
    received.assign(bytes.begin(), bytes.end());
    return !received.empty();
  }
  std::vector<std::uint8_t> received;
};

class EchoExchange final : public ForwardedExchange {
 public:
  explicit EchoExchange(std::vector<std::uint8_t> bytes) : bytes_(std::move(bytes)) {}
  const std::vector<std::uint8_t>& request_bytes() const override { return bytes_; }
  ReplyFramer& framer() override { return reply_; }
  Expected<std::vector<std::uint8_t>, std::string> reply_pdu() const override {
    if (reply_.received.empty()) return Unexpected{std::string("no reply")};
    return std::vector<std::uint8_t>(reply_.received.begin() + 1, reply_.received.end());
  }

 private:
  std::vector<std::uint8_t> bytes_;
  AnyReply reply_;
};

inline Expected<std::unique_ptr<ForwardedExchange>, std::string> echo_forward(
    std::uint8_t slave, std::span<const std::uint8_t> pdu) {
  std::vector<std::uint8_t> bytes{slave};
  bytes.insert(bytes.end(), pdu.begin(), pdu.end());
  return std::unique_ptr<ForwardedExchange>(std::make_unique<EchoExchange>(std::move(bytes)));
}

}  // namespace tiltgate::test
