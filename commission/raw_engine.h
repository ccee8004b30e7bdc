// One raw request as the engine sends it, for every front end: the vendor User App's command
// section. The bus's family builds the request from a function number and data (RawDescriptor,
// driver/family_commands.h); it is sent once, and the bytes each way, the checksum's verdict and
// the reply decoded are one ExchangeEvent (commission/commission_events.h). Nothing printed.
#pragma once

#include <boost/asio/awaitable.hpp>
#include <cstdint>
#include <string>

#include "commission/commission_bus.h"
#include "commission/commission_events.h"
#include "driver/family_commands.h"

namespace tiltgate {

struct RawOptions {
  std::int64_t function = 0;
  std::string data;  // hex bytes; empty: none
};

// Sends the request to the bus's one sensor and returns the exit code: 0 answered, 1 no reply
// or refused by the device, 2 a request that cannot be made (FailedEvent).
boost::asio::awaitable<int> raw_exchange(CommissionBus& bus, const RawOptions& raw,
                                         FamilyCommandsList commands, const EventSink& report,
                                         const bool& stopping);

}  // namespace tiltgate
