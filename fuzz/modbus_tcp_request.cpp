// The Modbus TCP side a client reaches first (modbus_tcp/modbus_request.h): the frame assembler
// fed a byte stream in random-sized reads, each ADU it yields parsed as the server would, and
// the whole input parsed as one ADU as well.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <span>
#include <variant>

#include "fuzz/chunks.h"
#include "modbus_tcp/modbus_request.h"

using namespace tiltgate;
using fuzz::check;

namespace {

void parse_one(std::span<const std::uint8_t> adu) {
  ParsedAdu parsed = parse_adu(adu);
  if (auto* rejected = std::get_if<RejectedRequest>(&parsed)) {
    // An exception reply echoes the MBAP transaction id, protocol id and unit id.
    check(rejected->reply.size() >= mbap_header_size + 2);
    check(std::equal(adu.begin(), adu.begin() + 4, rejected->reply.begin()));
    check(rejected->reply[6] == adu[6]);
  } else if (auto* request = std::get_if<ModbusRequest>(&parsed)) {
    check(request->unit_id == adu[6]);
    check(request->transaction_id == ((adu[0] << 8) | adu[1]));
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::span<const std::uint8_t> input(data, size);
  if (input.size() >= mbap_header_size) parse_one(input);

  fuzz::Chunks reads(input);
  ModbusFrameAssembler frames;
  while (!reads.done()) {
    auto space = frames.space();
    check(!space.empty());  // an incomplete frame is always shorter than the buffer
    auto piece = reads.next(space.size());
    std::copy(piece.begin(), piece.end(), space.begin());
    frames.commit(piece.size());
    for (;;) {
      auto next = frames.next();
      if (auto* adu = std::get_if<std::span<const std::uint8_t>>(&next)) {
        check(adu->size() >= mbap_header_size && adu->size() <= max_adu_size);
        auto size = adu_size(adu->first<mbap_header_size>());
        check(size.has_value() && *size == adu->size());
        parse_one(*adu);
        frames.pop();
      } else if (std::holds_alternative<FramingError>(next)) {
        return 0;  // the server closes the connection here
      } else {
        break;  // NeedMore
      }
    }
  }
  return 0;
}
