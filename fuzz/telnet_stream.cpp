// What a device server sends over RFC 2217 (device_server/): the Telnet reader fed a byte
// stream in random-sized reads must take out the same data and commands as when fed it whole,
// keep every subnegotiation bounded, and give back exactly the data that escape() sent; every
// subnegotiation's payload is read as a COM-PORT-OPTION answer.
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "device_server/com_port_option.h"
#include "device_server/telnet_codec.h"
#include "fuzz/chunks.h"

using namespace tiltgate;
using tiltgate::fuzz::check;

namespace {

struct Taken {
  std::vector<std::uint8_t> data;
  std::vector<telnet::Command> commands;
};

Taken take_in_pieces(fuzz::Chunks chunks) {
  Taken taken;
  telnet::Reader reader;
  while (!chunks.done()) {
    const auto piece = chunks.next();
    std::vector<std::uint8_t> buffer(piece.begin(), piece.end());
    const std::size_t data = reader.take(buffer, taken.commands);
    check(data <= buffer.size());
    taken.data.insert(taken.data.end(), buffer.begin(), buffer.begin() + std::ptrdiff_t(data));
  }
  return taken;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::span<const std::uint8_t> input(data, size);
  const fuzz::Chunks chunks(input);
  const Taken pieces = take_in_pieces(chunks);

  std::vector<std::uint8_t> whole(chunks.stream().begin(), chunks.stream().end());
  std::vector<telnet::Command> commands;
  telnet::Reader reader;
  whole.resize(reader.take(whole, commands));
  check(whole == pieces.data);
  check(commands.size() == pieces.commands.size());
  for (std::size_t i = 0; i < commands.size(); ++i) {
    check(commands[i].verb == pieces.commands[i].verb);
    check(commands[i].option == pieces.commands[i].option);
    check(commands[i].payload == pieces.commands[i].payload);
    check(commands[i].payload.size() <= 64);
    if (const auto answer = rfc2217::read_answer(commands[i].payload)) {
      rfc2217::Acknowledgements acks({.baud = 19200, .data_bits = 8, .parity = Parity::even, .stop_bits = 1});
      acks.take(*answer);
      (void)acks.missing();
    }
  }

  // Whatever the data, escaped it comes back the same.
  std::vector<std::uint8_t> escaped;
  telnet::escape(chunks.stream(), escaped);
  std::vector<telnet::Command> none;
  telnet::Reader fresh;
  escaped.resize(fresh.take(escaped, none));
  check(none.empty());
  check(escaped == std::vector<std::uint8_t>(chunks.stream().begin(), chunks.stream().end()));
  return 0;
}
