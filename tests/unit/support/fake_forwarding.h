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

class EchoExchange final : public ForwardedExchange, private ReplyFramer {
 public:
  explicit EchoExchange(std::vector<std::uint8_t> bytes) : bytes_(std::move(bytes)) {}
  const std::vector<std::uint8_t>& request_bytes() const override { return bytes_; }
  ReplyFramer& framer() override { return *this; }
  Expected<std::vector<std::uint8_t>, std::string> reply_pdu() const override {
    if (reply_.empty()) return Unexpected{std::string("no reply")};
    return std::vector<std::uint8_t>(reply_.begin() + 1, reply_.end());
  }

 private:
  void reset() override { reply_.clear(); }
  bool feed(std::span<const std::uint8_t> bytes) override {
    reply_.assign(bytes.begin(), bytes.end());
    return !reply_.empty();
  }
  std::vector<std::uint8_t> bytes_;
  std::vector<std::uint8_t> reply_;
};

inline Expected<std::unique_ptr<ForwardedExchange>, std::string> echo_forward(
    std::uint8_t slave, std::span<const std::uint8_t> pdu) {
  std::vector<std::uint8_t> bytes{slave};
  bytes.insert(bytes.end(), pdu.begin(), pdu.end());
  return std::unique_ptr<ForwardedExchange>(std::make_unique<EchoExchange>(std::move(bytes)));
}

}  // namespace tiltgate::test
