// How `tiltgate scan` finds Rieker sensors (driver/scan.h): Check Address (function 4) to one
// address, which the sensor there answers with an ACK; and, on request only, Get Address
// (function 3) to the broadcast address, which every sensor answers with its own address, so
// it works only with one sensor on the bus ("Digital RS485 Communications").
#pragma once

#include <chrono>
#include <cstdint>

#include "driver/scan.h"
#include "rieker/reply_framer.h"

namespace tiltgate::rieker {

boost::asio::awaitable<ProbeResult> check_address_probe(Line& line, const ProbeSetup& setup);
boost::asio::awaitable<ProbeResult> broadcast_get_address_probe(Line& line,
                                                                const ProbeSetup& setup);

// A probe and its reply on the wire at `baud` (8N1), with the 1 ms the master keeps between
// packets; the manual gives no turnaround ("as fast as possible").
std::chrono::microseconds probe_time(std::uint32_t baud);

// What one probe found, from its framer after the Line's exchange: a reply that answers it
// (an ACK or a NAK from the sensor's address, its address), bytes that failed their CRC (two sensors answering at once), or
// nothing. Pure, for tests.
ProbeResult probe_outcome(const RiekerReplyFramer& framer);

}  // namespace tiltgate::rieker
