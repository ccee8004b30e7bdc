// How `tiltgate scan` finds the sensors on a bus: each protocol probes one address with the
// cheapest request its sensors answer, and says what came back. The scan (gateway/) walks the
// addresses, times the probes and reads the identity of those that answered through the
// family's driver.
#pragma once

#include <boost/asio/awaitable.hpp>
#include <chrono>
#include <cstdint>
#include <optional>
#include <span>
#include <string>

#include "driver/family_options.h"
#include "driver/line.h"

namespace tiltgate {

enum class ProbeOutcome : std::uint8_t {
  answered,  // a valid reply: a sensor is there
  silent,    // nothing valid came back in time
  // Bytes came back that failed their checksum or made no sense as the reply: most likely two
  // sensors answering at once (two sensors at one address), or noise on the line.
  garbled,
  failed,  // the port failed or the line was stopped: the scan ends
};

struct ProbeResult {
  ProbeOutcome outcome = ProbeOutcome::silent;
  // The address that answered: the one probed, or the sensor's own for a broadcast.
  std::optional<std::uint32_t> address;
  std::string detail;  // for the user: "bad CRC", "exception 1 (illegal function)"
};

// What a probe is given: one address, and what the bus and the family's keys say.
struct ProbeSetup {
  std::uint32_t address = 0;
  std::uint32_t master_address = 0;  // protocols where the master has an address
  std::chrono::milliseconds timeout{20};
  // The family's [[sensor]] keys as the command line or configuration gave them (a device
  // profile, ...); empty when none were given.
  FamilyOptions options;
};

using ProbeFunction = boost::asio::awaitable<ProbeResult> (*)(Line& line, const ProbeSetup& setup);

// One protocol's part of a scan (ProtocolDescriptor::scan).
struct ScanDescriptor {
  // The addresses scanned when the user gives no range: the addresses sensors are usually set
  // to, a subset of the protocol's addresses.
  std::uint32_t first = 0;
  std::uint32_t last = 0;
  // The addresses sensors ship with, documented by the vendor: scanned besides the range.
  std::span<const std::uint32_t> factory_addresses;
  // How long one probe and its reply take on the wire at `baud`, with the sensor's turnaround.
  // The scan's default probe time-out adds an allowance for USB adapters to it.
  std::chrono::microseconds (*probe_time)(std::uint32_t baud) = nullptr;
  ProbeFunction probe = nullptr;
  // One request every sensor answers with its own address, where the protocol has one (it works
  // only with one sensor on the bus: several replies collide). Null: the protocol has none.
  ProbeFunction ask_address = nullptr;
};

// The time `bytes` characters of `bits` bits each take on the wire at `baud`.
constexpr std::chrono::microseconds wire_time(std::size_t bytes, unsigned bits,
                                              std::uint32_t baud) {
  return std::chrono::microseconds(
      baud == 0 ? 0 : (std::int64_t(bytes) * bits * 1'000'000 + baud - 1) / baud);
}

}  // namespace tiltgate
