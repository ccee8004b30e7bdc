#include "device_server/rfc2217_session.h"

#include <doctest/doctest.h>

#include <vector>

namespace tiltgate {

using Bytes = std::vector<std::uint8_t>;

TEST_CASE("an RFC 2217 session agrees, refuses what it did not ask for once, and confirms") {
  Rfc2217Session session({.baud = 62500, .data_bits = 8, .parity = Parity::none, .stop_bits = 1});
  CHECK(Rfc2217Session::offer() ==
        Bytes{0xFF, 0xFB, 0, 0xFF, 0xFB, 3, 0xFF, 0xFB, 44, 0xFF, 0xFD, 0, 0xFF, 0xFD, 3});
  // ser2net's offers on accept (docs/operations.md, "Serial device servers"): WILL ECHO is
  // refused once, DO COM-PORT-OPTION is the agreement.
  Bytes offers{0xFF, 0xFB, 0x01, 0xFF, 0xFB, 0x01, 0xFF, 0xFD, 0x2C, 0x42};
  CHECK(session.take(offers) == 1);
  CHECK(session.agreed());
  CHECK(session.take_replies() == Bytes{0xFF, 0xFE, 0x01});
  CHECK(session.take_replies().empty());
  CHECK_FALSE(session.confirmed());
  Bytes answers{0xFF, 0xFA, 44, 101, 0, 0, 0xF4, 0x24, 0xFF, 0xF0, 0xFF, 0xFA, 44, 102, 8,
                0xFF, 0xF0, 0xFF, 0xFA, 44, 103, 1, 0xFF, 0xF0, 0xFF, 0xFA, 44, 104, 1, 0xFF, 0xF0};
  CHECK(session.take(answers) == 0);
  CHECK(session.confirmed());
  CHECK_FALSE(session.refusal());
  const Bytes data{0x01, 0xFF};
  const auto wire = session.escaped(data);
  CHECK(Bytes(wire.begin(), wire.end()) == Bytes{0x01, 0xFF, 0xFF});
}

TEST_CASE("an RFC 2217 session says why the server cannot be used as asked") {
  Rfc2217Session refused({.baud = 19200, .data_bits = 8, .parity = Parity::even, .stop_bits = 1});
  Bytes dont{0xFF, 0xFE, 44};
  refused.take(dont);
  REQUIRE(refused.refusal());
  CHECK(refused.refusal()->find("refused RFC 2217's COM-PORT-OPTION") != std::string::npos);

  Rfc2217Session other({.baud = 19200, .data_bits = 8, .parity = Parity::even, .stop_bits = 1});
  Bytes parity{0xFF, 0xFA, 44, 103, 1, 0xFF, 0xF0};
  other.take(parity);
  REQUIRE(other.refusal());
  CHECK(*other.refusal() == "the server set parity none, not even");
}

}  // namespace tiltgate
