// The engine's results as the text a person reads (commission/commission_events.h): what
// `tiltgate scan` and `tiltgate raw` print, and what the web console shows as their output.
// Pure.
#pragma once

#include <string>

#include "commission/commission_events.h"

namespace tiltgate {

// The table of what answered, the notes on sensors found at several rates, and the summary:
// one line each, every line ending in a newline.
std::string scan_result_text(const ScanFinishedEvent& finished);

// "sent:     ..." and "received: ..." and, when answered, the reply decoded: one line each.
std::string exchange_text(const ExchangeEvent& exchange);

// What the checksum said of the reply: its verdict, or "nothing" (with why bytes that came
// were not one).
std::string received_verdict(const ExchangeEvent& exchange);

}  // namespace tiltgate
