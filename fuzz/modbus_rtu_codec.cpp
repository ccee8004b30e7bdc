// The Modbus RTU codec (modbus_rtu/): the first bytes of the input choose a request (read,
// write single, write multiple, or a raw pass-through PDU); the rest is read both as that
// request's reply frame and, in random-sized reads, by the frame parser for replies and for
// requests. Every frame the parser finds must be exactly as long as frame_length() says (or
// CRC-delimited) and is checked with parse_reply() against the request.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "fuzz/chunks.h"
#include "modbus_rtu/codec.h"
#include "modbus_rtu/frame_length.h"
#include "modbus_rtu/frame_parser.h"

using namespace tiltgate::modbus_rtu;
using tiltgate::Expected;
using tiltgate::Unexpected;
using tiltgate::fuzz::check;

namespace {

constexpr std::size_t kRequestBytes = 6;  // kind, slave, address (2), count (2)

std::optional<Request> choose_request(std::span<const std::uint8_t> head) {
  std::uint8_t slave = head[1];
  auto address = static_cast<std::uint16_t>((head[2] << 8) | head[3]);
  auto count = static_cast<std::uint16_t>((head[4] << 8) | head[5]);
  Expected<Request, CodecError> request = Unexpected{CodecError::bad_slave};
  switch (head[0] % 5) {
    case 0: request = read_request(slave, RegisterBank::holding, address, count); break;
    case 1: request = read_request(slave, RegisterBank::input, address, count); break;
    case 2: request = write_single_request(slave, address, count); break;
    case 3: {
      std::vector<std::uint16_t> values(count % 130, address);
      request = write_multiple_request(slave, address, values);
      break;
    }
    default: request = raw_request(slave, head.subspan(2)); break;
  }
  if (!request) return std::nullopt;
  return *request;
}

void check_reply(const Request& request, std::span<const std::uint8_t> frame) {
  auto reply = parse_reply(request, frame);
  if (!reply) return;
  check(reply->slave == request.slave);
  check(reply->function == request.function);
  check(!reply->pdu.empty() && reply->pdu.size() <= kMaxPduSize);
}

void parse_stream(FrameKind kind, std::optional<Expectation> expect,
                  std::span<const std::uint8_t> input, const std::optional<Request>& request) {
  tiltgate::fuzz::Chunks reads(input);
  RtuFrameParser parser(kind, expect);
  while (!reads.done()) {
    parser.feed(reads.next());
    while (auto frame = parser.next()) {
      check(frame->size() >= 4 && frame->size() <= kMaxFrameSize);
      auto length = frame_length(kind, *frame);
      check(length.has_value());
      check(*length == kLengthByCrc || *length == frame->size());
      if (request && kind == FrameKind::reply) check_reply(*request, *frame);
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::span<const std::uint8_t> input(data, size);
  if (input.size() < kRequestBytes) return 0;
  std::optional<Request> request = choose_request(input.first(kRequestBytes));
  auto rest = input.subspan(kRequestBytes);
  if (request) {
    check(request->frame.size() >= 4 && request->frame.size() <= kMaxFrameSize);
    check_reply(*request, rest);
  }
  for (std::size_t i = 0; i <= rest.size() && i < 16; ++i) (void)frame_length(FrameKind::reply, rest.first(i));

  std::optional<Expectation> expect;
  if (request) expect = Expectation{request->slave, request->function};
  parse_stream(FrameKind::reply, expect, rest, request);
  parse_stream(FrameKind::reply, std::nullopt, rest, request);
  parse_stream(FrameKind::request, std::nullopt, rest, std::nullopt);
  return 0;
}
