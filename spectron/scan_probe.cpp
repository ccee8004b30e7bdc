#include "spectron/scan_probe.h"

namespace tiltgate::spectron {

namespace {

// The longer protocol's request (":01663" CR LF) and reply (":0166" four hex digits, LRC, CR LF).
constexpr std::size_t kProbeCharacters = 9 + 15;
constexpr unsigned kBitsPerCharacter = 11;  // a 9th bit (or parity) and one stop bit
constexpr std::chrono::microseconds kTurnaround{2000};

boost::asio::awaitable<ProbeResult> read_sensor_probe(Line& line, const ProbeSetup& setup,
                                                      Protocol protocol) {
  auto transaction = DynaTransaction::make(protocol, int(setup.address),
                                           DynaRequest{DynaRequest::Kind::read_sensor});
  if (!transaction)
    co_return ProbeResult{ProbeOutcome::silent, std::nullopt, transaction.error()};
  LineRequest request = transaction->line_request();
  request.timeout = setup.timeout;
  request.retries = 0;  // a scan asks each address once
  const auto done = co_await line.transact(std::move(request));
  if (!done && done.error() != LineError::timeout)
    co_return ProbeResult{ProbeOutcome::failed, std::nullopt, to_string(done.error())};
  co_return probe_outcome(*transaction, setup.address, done.has_value());
}

}  // namespace

boost::asio::awaitable<ProbeResult> nine_bit_read_sensor_probe(Line& line,
                                                               const ProbeSetup& setup) {
  co_return co_await read_sensor_probe(line, setup, Protocol::nine_bit);
}

boost::asio::awaitable<ProbeResult> ascii_read_sensor_probe(Line& line, const ProbeSetup& setup) {
  co_return co_await read_sensor_probe(line, setup, Protocol::modbus_ascii);
}

std::chrono::microseconds probe_time(std::uint32_t baud) {
  return wire_time(kProbeCharacters, kBitsPerCharacter, baud) + kTurnaround;
}

ProbeResult probe_outcome(const DynaTransaction& transaction, std::uint32_t address,
                          bool replied) {
  if (replied) {
    auto answer = transaction.answer();
    // A 9-bit reply carries no check: a line that is no number is most likely two modules
    // talking at once.
    if (!answer) return {ProbeOutcome::garbled, std::nullopt, describe(answer.error())};
    return {ProbeOutcome::answered, address, ""};
  }
  const std::string rejected = transaction.line_request().framer->report().rejected_verdict;
  if (!rejected.empty()) return {ProbeOutcome::garbled, std::nullopt, rejected};
  return {ProbeOutcome::silent, std::nullopt, ""};
}

}  // namespace tiltgate::spectron
