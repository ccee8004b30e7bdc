// How many Modbus TCP requests the server answered, by function code, and how many of those
// answers were exceptions, by function and exception code: the /metrics families
// tiltgate_modbus_requests_total and tiltgate_modbus_exceptions_total. Counted from the reply
// sent, so requests answered by the parser, the register maps or a passed-through device all
// count the same way. Counted from any thread.
#pragma once

#include <array>
#include <atomic>
#include <mutex>
#include <cstdint>
#include <map>
#include <span>
#include <vector>

namespace tiltgate {

// Requests answered with one function code, and answers that were one exception code to one
// function.
struct ModbusFunctionCount {
  std::uint8_t function = 0;
  std::uint64_t count = 0;
};
struct ModbusExceptionCount {
  std::uint8_t function = 0;
  std::uint8_t exception = 0;
  std::uint64_t count = 0;
};

class ModbusRequestCounts {
 public:
  // `reply` is a whole Modbus TCP ADU (MBAP header, function, data); shorter ones are ignored.
  void note_reply(std::span<const std::uint8_t> reply);

  std::vector<ModbusFunctionCount> requests() const;     // functions seen, in code order
  std::vector<ModbusExceptionCount> exceptions() const;  // (function, code) seen, in order

 private:
  std::array<std::atomic<std::uint64_t>, 128> by_function_{};
  mutable std::mutex exceptions_mutex_;  // exceptions are the rare case: a lock is cheap enough
  std::map<std::pair<std::uint8_t, std::uint8_t>, std::uint64_t> exceptions_;
};

}  // namespace tiltgate
