// A virtual Dyna RS485 bus on a pseudo-terminal: the gateway (or a test) opens slave_path()
// (or the stable link path) as if it were a USB-RS485 adapter, and the simulated modules on
// the bus answer its requests in the protocol chosen in the options. Used by the sim tests,
// the demo and `tiltgate sim spectron`.
//
// 9-bit addressing on a pseudo-terminal. A pty carries bytes, not parity bits, so the ninth
// bit that marks an address byte cannot reach the simulator. In nine_bit mode the simulator
// therefore uses a framing convention that exists ONLY in simulation:
//   the address byte is the first byte ever received, the first byte after a CR LF, or the
//   first byte after 20 ms of silence that followed part of a command body.
// (Silence right after an address byte does not restart framing: the serial line sends the
// address byte, drains it, switches parity, then sends the body, and on a busy machine that
// switch can take longer than 20 ms.) The real UART path (mark parity for the address byte,
// space parity for the body, in serial/serial_line) does not depend on this convention; it
// just happens to produce byte streams the convention splits correctly.
//
// The pty, pacing, plugging and collisions are the simulated bus's (serial/simulated_bus.h).
#pragma once

#include <boost/asio/io_context.hpp>
#include <chrono>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "driver/expected.h"
#include "serial/simulated_bus.h"
#include "spectron/ascii_codec.h"
#include "spectron/protocol.h"
#include "spectron/simulated_dyna.h"

namespace tiltgate::spectron {

// The silence after part of a 9-bit command body that makes the next byte an address byte.
inline constexpr std::chrono::milliseconds kNineBitResyncSilence{20};

struct DynaSimulatorOptions : SimulatedBusOptions {
  Protocol protocol = Protocol::nine_bit;
  std::vector<SimulatedDynaOptions> sensors;
};

struct DynaSimulatorCounters : SimulatedBusCounters {
  std::uint64_t lrc_errors = 0;  // Modbus-ASCII frames with a bad LRC (never answered)
  std::uint64_t malformed = 0;   // frames or 9-bit commands that could not be read
};

class DynaSimulator final : public SimulatedBus {
 public:
  DynaSimulator(boost::asio::io_context& io, DynaSimulatorOptions options);
  ~DynaSimulator() override;

  std::size_t sensor_count() const override { return sensors_.size(); }
  std::string what() const override;
  // "counts ADDRESS N": the module's raw counts (-32768..32767), fixed from now on.
  Expected<Done, std::string> command(std::string_view line) override;

  Protocol protocol() const { return options_.protocol; }
  SimulatedDyna& sensor(std::size_t index) { return sensors_.at(index); }
  // The module now at `address` (it follows writes to EEPROM location 16), or nullptr.
  SimulatedDyna* sensor_by_address(std::uint8_t address);

  DynaSimulatorCounters counters() const;

 private:
  struct Framing;  // the request framing of the current pseudo-terminal

  void receive(std::span<const std::uint8_t> bytes) override;
  void reset_framing() override;
  // A garbled reply: its second character replaced by one that neither protocol sends there
  // (a 9-bit number, a Modbus-ASCII hex digit).
  void garble(std::vector<std::uint8_t>& reply) const override;
  void on_nine_bit_bytes(std::span<const std::uint8_t> bytes);
  void on_ascii_bytes(std::span<const std::uint8_t> bytes);

  DynaSimulatorOptions options_;
  std::vector<SimulatedDyna> sensors_;
  std::unique_ptr<Framing> framing_;  // a fresh one for every (re)open
  std::uint64_t lrc_errors_ = 0;
  std::uint64_t malformed_ = 0;
};

}  // namespace tiltgate::spectron
