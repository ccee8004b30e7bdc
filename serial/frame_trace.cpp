#include "serial/frame_trace.h"

#include <algorithm>
#include <fmt/format.h>

#include "driver/hex.h"

namespace tiltgate {

std::string traced_request(std::span<const std::uint8_t> bytes, std::size_t address_bytes) {
  address_bytes = std::min(address_bytes, bytes.size());
  if (address_bytes == 0) return "-> " + hex_bytes(bytes);
  std::string line = "-> [" + hex_bytes(bytes.first(address_bytes)) + "]";
  if (address_bytes < bytes.size()) line += " " + hex_bytes(bytes.subspan(address_bytes));
  return line;
}

std::vector<std::string> traced_reply(std::span<const std::uint8_t> received,
                                      const FramerReport& report,
                                      std::chrono::milliseconds delay) {
  const std::string verdict =
      report.reply_verdict.empty() ? std::string("reply") : report.reply_verdict;
  const std::span<const std::uint8_t> reply(report.reply);
  const auto found =
      reply.empty() ? received.end()
                    : std::search(received.begin(), received.end(), reply.begin(), reply.end());
  if (found == received.end()) {
    // A framer without a report, or a reply that is not found whole among the bytes read (a
    // noise byte inside it was dropped): show what was read.
    std::string line =
        fmt::format("<- {} ({} ms, {}", hex_bytes(received), delay.count(), verdict);
    if (!report.rejected_verdict.empty()) line += "; also " + report.rejected_verdict;
    return {line + ")"};
  }
  std::vector<std::string> lines;
  const auto before = received.first(static_cast<std::size_t>(found - received.begin()));
  if (!before.empty()) {
    const std::string& rejected = report.rejected_verdict;
    lines.push_back(fmt::format("<- {} ({})", hex_bytes(before),
                                rejected.empty() ? std::string("skipped") : rejected));
  }
  lines.push_back(fmt::format("<- {} ({} ms, {})", hex_bytes(reply), delay.count(), verdict));
  const auto after = received.subspan(before.size() + reply.size());
  if (!after.empty()) {
    lines.push_back(fmt::format("<- {} (ignored: after the reply)", hex_bytes(after)));
  }
  return lines;
}

std::string traced_timeout(std::span<const std::uint8_t> received, const FramerReport& report,
                           std::chrono::milliseconds timeout) {
  if (received.empty()) return fmt::format("no reply within {} ms", timeout.count());
  std::string line =
      fmt::format("<- {} (no reply within {} ms", hex_bytes(received), timeout.count());
  if (!report.rejected_verdict.empty()) line += ": " + report.rejected_verdict;
  return line + ")";
}

std::string traced_late(std::span<const std::uint8_t> discarded,
                        std::chrono::milliseconds after_request) {
  return fmt::format("<- {} (discarded: late, {} ms after the request)", hex_bytes(discarded),
                     after_request.count());
}

}  // namespace tiltgate
