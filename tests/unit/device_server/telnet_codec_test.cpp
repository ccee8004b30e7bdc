#include "device_server/telnet_codec.h"

#include <doctest/doctest.h>

#include <vector>

namespace tiltgate::telnet {

using Bytes = std::vector<std::uint8_t>;

TEST_CASE("Telnet doubles a 0xFF data byte and nothing else") {
  Bytes out;
  const Bytes data{0x01, 0xFF, 0x9C, 0x0D, 0x00};
  escape(data, out);
  CHECK(out == Bytes{0x01, 0xFF, 0xFF, 0x9C, 0x0D, 0x00});
  CHECK(subnegotiation(kComPortOption, Bytes{1, 0, 0, 0xFF, 0xFF}) ==
        Bytes{kIac, kSb, 44, 1, 0, 0, 0xFF, 0xFF, 0xFF, 0xFF, kIac, kSe});
}

TEST_CASE("the Telnet reader keeps data bytes and takes out the commands") {
  // What ser2net sends on accept (docs/operations.md, "Serial device servers"), a reply with
  // an escaped 0xFF, and an RFC 2217 answer between them.
  Bytes wire{0xFF, 0xFB, 0x03, 0xFF, 0xFD, 0x2C, 0x01, 0x03, 0xFF, 0xFF, 0x9C,
             0xFF, 0xFA, 0x2C, 0x65, 0x00, 0x00, 0x25, 0x80, 0xFF, 0xF0, 0x42};
  Reader reader;
  std::vector<Command> commands;
  const std::size_t data = reader.take(wire, commands);
  CHECK(Bytes(wire.begin(), wire.begin() + std::ptrdiff_t(data)) == Bytes{0x01, 0x03, 0xFF, 0x9C, 0x42});
  REQUIRE(commands.size() == 3);
  CHECK(commands[0].verb == kWill);
  CHECK(commands[0].option == kSuppressGoAhead);
  CHECK(commands[1].verb == kDo);
  CHECK(commands[1].option == kComPortOption);
  CHECK(commands[2].verb == kSb);
  CHECK(commands[2].payload == Bytes{0x65, 0x00, 0x00, 0x25, 0x80});
}

TEST_CASE("a command split across reads is put together") {
  Reader reader;
  std::vector<Command> commands;
  Bytes first{0x10, 0xFF};
  CHECK(reader.take(first, commands) == 1);
  Bytes second{0xFA, 0x2C, 0x66};
  CHECK(reader.take(second, commands) == 0);
  Bytes third{0x08, 0xFF};
  CHECK(reader.take(third, commands) == 0);
  CHECK(commands.empty());
  Bytes fourth{0xF0, 0xFF};
  CHECK(reader.take(fourth, commands) == 0);
  REQUIRE(commands.size() == 1);
  CHECK(commands[0].payload == Bytes{0x66, 0x08});
  Bytes fifth{0xFF, 0x20};  // the 0xFF before was the first half of an escaped data byte
  const std::size_t data = reader.take(fifth, commands);
  CHECK(Bytes(fifth.begin(), fifth.begin() + std::ptrdiff_t(data)) == Bytes{0xFF, 0x20});
}

TEST_CASE("an endless subnegotiation is cut, not held") {
  Reader reader;
  std::vector<Command> commands;
  Bytes wire{0xFF, 0xFA, 0x2C};
  wire.insert(wire.end(), 10000, 0x01);
  wire.push_back(0xFF);
  wire.push_back(0xF0);
  CHECK(reader.take(wire, commands) == 0);
  REQUIRE(commands.size() == 1);
  CHECK(commands[0].payload.size() == 64);
}

}  // namespace tiltgate::telnet
