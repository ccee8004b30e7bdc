// How `tiltgate scan` finds Dyna modules (driver/scan.h): a Read Sensor to one module address
// ("A" in the 9-bit protocol, 0x66 in the Modbus-ASCII one), which the module there answers
// with its raw counts. Neither protocol has a request every module answers.
#pragma once

#include <chrono>
#include <cstdint>

#include "driver/scan.h"
#include "spectron/dyna_transactions.h"

namespace tiltgate::spectron {

boost::asio::awaitable<ProbeResult> nine_bit_read_sensor_probe(Line& line, const ProbeSetup& setup);
boost::asio::awaitable<ProbeResult> ascii_read_sensor_probe(Line& line, const ProbeSetup& setup);

// A probe and its reply on the wire at `baud` (11 bits a character in both protocols), with
// 2 ms for the module to answer: the application note gives no turnaround.
std::chrono::microseconds probe_time(std::uint32_t baud);

// What one probe found, from its transaction after the Line's exchange (`replied`: the framer
// held a whole reply): a number read, a reply that is not one or bytes that failed their LRC
// (two modules answering at once), or nothing. Pure, for tests.
ProbeResult probe_outcome(const DynaTransaction& transaction, std::uint32_t address, bool replied);

}  // namespace tiltgate::spectron
