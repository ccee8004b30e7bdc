// One Dyna request/reply exchange in either protocol, so the driver speaks in what it asks
// ("read EEPROM 4") and not in how each protocol spells it. Builds the wire bytes with the
// codec, owns the reply framer the Line feeds, and reads the reply out of it afterwards.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "driver/expected.h"
#include "driver/line.h"
#include "spectron/protocol.h"
#include "spectron/reply_framers.h"

namespace tiltgate::spectron {

// What the driver asks a module. The same six commands exist in both protocols.
struct DynaRequest {
  enum class Kind {
    reset,             // 9-bit "0", Modbus-ASCII 0x65
    read_sensor,       // "A", 0x66: raw counts
    read_temperature,  // "C", 0x67: raw temperature
    read_eeprom,       // "3", 0x69: the word at `location`
    write_eeprom,      // "E", 0x68: `value` to `location`
    firmware,          // "F" (free text), 0x6A (a word shown "HH.LL", A7)
  };
  Kind kind = Kind::read_sensor;
  std::int64_t location = 0;
  std::int64_t value = 0;
};
const char* request_name(DynaRequest::Kind kind);  // "read sensor", for logs

// What a reply said: a number (counts, temperature, an EEPROM word), the firmware text, or, for
// reset and write, only that it came.
struct DynaAnswer {
  std::int32_t number = 0;
  std::string text;
};

class DynaTransaction {
 public:
  // Nothing is built for an argument the protocol cannot carry (an address out of the
  // protocol's range, a location outside the memory map): the error says why.
  static Expected<DynaTransaction, std::string> make(Protocol protocol, int address,
                                                     const DynaRequest& request);

  // The request for Line::transact; it points at this transaction's framer, which lives on the
  // heap, so the transaction may be moved but must outlive the transact() call.
  LineRequest line_request() const;
  // Modbus-ASCII replies dropped for a bad LRC (the 9-bit protocol has no check).
  std::uint64_t checksum_errors() const;
  // The reply, read as this request's answer. Only after the Line reported a complete reply.
  Expected<DynaAnswer, ReplyError> answer() const;

 private:
  DynaTransaction(Protocol protocol, DynaRequest request) : protocol_(protocol), request_(request) {}
  Expected<DynaAnswer, ReplyError> nine_bit_answer(const std::string& line) const;
  Expected<DynaAnswer, ReplyError> ascii_answer(const AsciiFrame& reply) const;

  Protocol protocol_;
  DynaRequest request_;
  std::vector<std::uint8_t> bytes_;
  std::size_t address_bytes_ = 0;
  AsciiFrame ascii_request_;                     // Modbus-ASCII: what the reply must answer
  std::unique_ptr<NineBitReplyFramer> nine_bit_;  // exactly one of the two framers is set
  std::unique_ptr<AsciiReplyFramer> ascii_;
};

}  // namespace tiltgate::spectron
