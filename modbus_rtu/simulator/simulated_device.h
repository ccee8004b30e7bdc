// A model of one Modbus RTU slave: holding and input register banks, answering FC 3, 4, 6 and
// 16 as the Application Protocol (6.3, 6.4, 6.6, 6.12 and 7.) describes, FC 17 and 43 / 14
// where it is given an identification (modbus_rtu/simulator/simulated_identification.h), and exception 01
// for any other function, 02 for registers it does not have, 03 for a bad count or a value
// its write check refuses. Pure: whole request frames in (CRC already checked), reply frames
// out, so tests drive it without a pseudo-terminal.
//
// Choices where the spec leaves room (tested): the checks run in the spec's order (function,
// then count, then address range, then the value); broadcast (address 0) writes are carried
// out and never answered, broadcast reads are ignored; the faults apply to requests addressed
// to this slave only.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <vector>

#include "modbus_rtu/codec.h"
#include "modbus_rtu/simulator/simulated_identification.h"

namespace tiltgate::modbus_rtu {

// Faults a test can inject; each counts replies (or would-be replies) from now on.
struct DeviceFaults {
  int silent = 0;       // answer nothing
  int corrupt_crc = 0;  // flip the reply's CRC low byte
  int late = 0;         // answer `late_by` later than usual
  std::chrono::milliseconds late_by{500};
};

struct DeviceReply {
  Bytes frame;
  std::chrono::milliseconds delay{0};  // on top of the simulator's usual latency
};

class SimulatedDevice {
 public:
  // Refuses a write of `value` to holding register `address` with exception 03 when false.
  using WriteCheck = std::function<bool(std::uint16_t address, std::uint16_t value)>;

  SimulatedDevice(std::uint8_t slave, std::size_t holding_count, std::size_t input_count);

  // The reply to `request` (one whole frame, CRC included and checked), or nullopt: not for
  // this slave, a broadcast, or a silent fault.
  std::optional<DeviceReply> respond(std::span<const std::uint8_t> request);

  std::uint8_t slave() const { return slave_; }
  std::vector<std::uint16_t>& holding() { return holding_; }
  std::vector<std::uint16_t>& input() { return input_; }
  const std::vector<std::uint16_t>& holding() const { return holding_; }
  const std::vector<std::uint16_t>& input() const { return input_; }
  void set_write_check(WriteCheck check) { write_check_ = std::move(check); }
  // What it answers to FC 17 and FC 43 / 14; by default neither (exception 01).
  void set_identification(SimulatedIdentification identification) {
    identification_ = std::move(identification);
  }
  DeviceFaults& faults() { return faults_; }
  std::uint64_t requests_handled() const { return requests_handled_; }

 private:
  // The reply PDU (function code onward), faults aside.
  Bytes answer(std::span<const std::uint8_t> pdu);
  Bytes answer_read(std::span<const std::uint8_t> pdu, const std::vector<std::uint16_t>& bank);
  Bytes answer_write_single(std::span<const std::uint8_t> pdu);
  Bytes answer_write_multiple(std::span<const std::uint8_t> pdu);
  bool write_allowed(std::uint16_t address, std::span<const std::uint16_t> values) const;

  std::uint8_t slave_;
  std::vector<std::uint16_t> holding_;
  std::vector<std::uint16_t> input_;
  WriteCheck write_check_;
  SimulatedIdentification identification_;
  DeviceFaults faults_;
  std::uint64_t requests_handled_ = 0;
};

}  // namespace tiltgate::modbus_rtu
