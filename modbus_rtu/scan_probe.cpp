#include "modbus_rtu/scan_probe.h"

#include <fmt/format.h>

#include "modbus_rtu/profile_reader.h"

namespace tiltgate::modbus_rtu {

namespace {

// The request (8 bytes) and a reply of up to 32 registers.
constexpr std::size_t kProbeBytes = 8 + 5 + 64;
constexpr unsigned kBitsPerCharacter = 11;  // 8 data bits, parity or a second stop bit
constexpr std::chrono::microseconds kTurnaround{5000};

// The profile's first read block, when the scan was given a profile (device = FILE).
std::optional<ReadBlock> first_block(const FamilyOptions& options) {
  const std::string path = options.text("device");
  if (path.empty()) return std::nullopt;
  auto profile = load_device_profile(path);
  if (!profile || profile->reads.empty()) return std::nullopt;
  return profile->reads.front();
}

}  // namespace

Expected<Request, CodecError> probe_request(std::uint8_t slave,
                                            const std::optional<ReadBlock>& block) {
  if (block) return read_request(slave, block->bank, block->address, block->count);
  const std::uint8_t pdu[] = {kReportServerId};
  return raw_request(slave, pdu);
}

namespace {

constexpr std::uint8_t kGatewayPathUnavailable = 0x0A;
constexpr std::uint8_t kGatewayTargetFailed = 0x0B;

boost::asio::awaitable<ProbeResult> probe(Adu adu, Line& line, const ProbeSetup& setup) {
  const std::uint32_t last = adu == Adu::mbap ? 255 : kMaxSlaveAddress;
  const std::uint32_t first = adu == Adu::mbap ? 0 : 1;
  if (setup.address < first || setup.address > last)
    co_return ProbeResult{ProbeOutcome::silent, std::nullopt, "not a slave address"};
  const std::optional<ReadBlock> block = first_block(setup.options);
  auto framer = AduFraming(adu).exchange(std::uint8_t(setup.address), [&](std::uint8_t slave) {
    return probe_request(slave, block);
  });
  if (!framer) co_return ProbeResult{ProbeOutcome::silent, std::nullopt, to_string(framer.error())};
  LineRequest line_request;
  line_request.bytes = (*framer)->request_bytes();
  line_request.framer = framer->get();
  line_request.timeout = setup.timeout;
  line_request.retries = 0;  // a scan asks each address once
  const auto done = co_await line.transact(std::move(line_request));
  if (!done && done.error() != LineError::timeout)
    co_return ProbeResult{ProbeOutcome::failed, std::nullopt, to_string(done.error())};
  co_return probe_outcome(**framer, setup.address, adu);
}

}  // namespace

boost::asio::awaitable<ProbeResult> device_probe(Line& line, const ProbeSetup& setup) {
  return probe(Adu::rtu, line, setup);
}

boost::asio::awaitable<ProbeResult> mbap_device_probe(Line& line, const ProbeSetup& setup) {
  return probe(Adu::mbap, line, setup);
}

std::chrono::microseconds probe_time(std::uint32_t baud) {
  return wire_time(kProbeBytes, kBitsPerCharacter, baud) + kTurnaround;
}

std::chrono::microseconds mbap_probe_time(std::uint32_t) { return std::chrono::milliseconds{20}; }

ProbeResult probe_outcome(const ModbusReplyFramer& framer, std::uint32_t address, Adu adu) {
  if (const auto& reply = framer.reply()) {
    if (!*reply) return {ProbeOutcome::answered, address, to_string(reply->error())};
    const std::optional<std::uint8_t> exception = (*reply)->exception;
    if (adu == Adu::mbap &&
        (exception == kGatewayTargetFailed || exception == kGatewayPathUnavailable))
      return {ProbeOutcome::silent, std::nullopt,
              fmt::format("exception {} ({})", *exception, exception_name(*exception))};
    if ((*reply)->exception)
      return {ProbeOutcome::answered, address,
              fmt::format("exception {} to function {}", *(*reply)->exception,
                          (*reply)->function)};
    return {ProbeOutcome::answered, address, ""};
  }
  if (!framer.report().rejected_verdict.empty())
    return {ProbeOutcome::garbled, std::nullopt, framer.report().rejected_verdict};
  return {ProbeOutcome::silent, std::nullopt, ""};
}

}  // namespace tiltgate::modbus_rtu
