#include "rieker/scan_probe.h"

#include <fmt/format.h>

namespace tiltgate::rieker {

namespace {

// Check Address and its ACK are 9 bytes; Get Address's reply 11.
constexpr std::size_t kProbeBytes = kMinFrameSize + kMinFrameSize + 2;
constexpr unsigned kBitsPerByte = 10;  // 8N1
constexpr std::chrono::microseconds kMasterGap{1000};

ProbeResult failed_line(LineError error) {
  return {ProbeOutcome::failed, std::nullopt, to_string(error)};
}

boost::asio::awaitable<ProbeResult> probe(Line& line, const ProbeSetup& setup,
                                          RequestResult request) {
  if (!request) co_return ProbeResult{ProbeOutcome::silent, std::nullopt, request.error().message};
  RiekerReplyFramer framer(*request);
  LineRequest line_request;
  line_request.bytes = encode(*request);
  line_request.framer = &framer;
  line_request.timeout = setup.timeout;
  line_request.retries = 0;  // a scan asks each address once
  const auto done = co_await line.transact(std::move(line_request));
  if (!done && done.error() != LineError::timeout) co_return failed_line(done.error());
  co_return probe_outcome(framer);
}

Route route_to(std::uint32_t address, const ProbeSetup& setup) {
  return Route{std::uint16_t(address), std::uint16_t(setup.master_address)};
}

}  // namespace

boost::asio::awaitable<ProbeResult> check_address_probe(Line& line, const ProbeSetup& setup) {
  if (setup.address < kMinSensorAddress || setup.address > kMaxSensorAddress)
    co_return ProbeResult{ProbeOutcome::silent, std::nullopt, "not a sensor address"};
  co_return co_await probe(line, setup, check_address_request(route_to(setup.address, setup)));
}

boost::asio::awaitable<ProbeResult> broadcast_get_address_probe(Line& line,
                                                                const ProbeSetup& setup) {
  co_return co_await probe(line, setup, get_address_request(route_to(kBroadcastAddress, setup)));
}

std::chrono::microseconds probe_time(std::uint32_t baud) {
  return wire_time(kProbeBytes, kBitsPerByte, baud) + kMasterGap;
}

ProbeResult probe_outcome(const RiekerReplyFramer& framer) {
  if (const auto& reply = framer.reply()) {
    // Get Address: the sensor's own address, in the reply's data.
    if (reply->function == std::uint16_t(Function::get_address)) {
      auto own = parse_address_reply(*reply);
      if (!own) return {ProbeOutcome::garbled, std::nullopt, describe(own.error())};
      return {ProbeOutcome::answered, *own, ""};
    }
    // Check Address: an ACK. A NAK still shows a sensor at the address it came from.
    auto ack = parse_ack(*reply);
    return {ProbeOutcome::answered, reply->src, ack ? "" : describe(ack.error())};
  }
  if (!framer.report().rejected_verdict.empty())
    return {ProbeOutcome::garbled, std::nullopt, "bad CRC"};
  return {ProbeOutcome::silent, std::nullopt, ""};
}

}  // namespace tiltgate::rieker
