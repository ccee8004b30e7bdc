#include "commission/event_text.h"

#include <fmt/format.h>

#include "driver/hex.h"

namespace tiltgate {

std::string scan_result_text(const ScanFinishedEvent& finished) {
  std::string text;
  if (!finished.found.empty()) {
    text += scan_header() + "\n";
    for (const FoundSensor& s : finished.found) text += scan_row(s) + "\n";
  }
  for (const RepeatedSensor& r : finished.repeated) text += repeated_note(r) + "\n";
  text += scan_summary(finished.found, finished.probes, finished.took) + "\n";
  return text;
}

std::string received_verdict(const ExchangeEvent& exchange) {
  if (exchange.answered) return exchange.verdict;
  return exchange.rejected_verdict.empty() ? "nothing"
                                           : "nothing valid (" + exchange.rejected_verdict + ")";
}

std::string exchange_text(const ExchangeEvent& exchange) {
  std::string text = "sent:     " + hex_bytes(exchange.sent);
  if (exchange.address_bytes > 0)
    text += fmt::format("  (the first {} with the 9th bit set)",
                        exchange.address_bytes == 1
                            ? std::string("byte")
                            : fmt::format("{} bytes", exchange.address_bytes));
  text += "\n";
  if (!exchange.answered) return text + "received: " + received_verdict(exchange) + "\n";
  text += fmt::format("received: {}  ({})\n", hex_bytes(exchange.received), exchange.verdict);
  return text + exchange.decoded + "\n";
}

}  // namespace tiltgate
