#include "device_server/com_port_option.h"

#include <doctest/doctest.h>

namespace tiltgate::rfc2217 {

using Bytes = std::vector<std::uint8_t>;

TEST_CASE("RFC 2217 requests set rate, data size, parity, stop bits and no flow control") {
  const auto requests = set_requests({.baud = 125000, .data_bits = 8, .parity = Parity::even, .stop_bits = 1});
  REQUIRE(requests.size() == 5);
  CHECK(requests[0] == Bytes{1, 0x00, 0x01, 0xE8, 0x48});  // 125000 big-endian
  CHECK(requests[1] == Bytes{2, 8});
  CHECK(requests[2] == Bytes{3, 3});  // even
  CHECK(requests[3] == Bytes{4, 1});
  CHECK(requests[4] == Bytes{5, 1});
  CHECK(parity_code(Parity::none) == 1);
  CHECK(parity_code(Parity::odd) == 2);
  CHECK(parity_code(Parity::mark) == 4);
  CHECK(parity_code(Parity::space) == 5);
}

TEST_CASE("the server's answers confirm the port, or say what it set instead") {
  const PortSetting asked{.baud = 62500, .data_bits = 8, .parity = Parity::none, .stop_bits = 1};
  Acknowledgements acks(asked);
  CHECK(acks.missing() == "baud rate, data size, parity, stop bits");
  acks.take(*read_answer(Bytes{101, 0x00, 0x00, 0xF4, 0x24}));
  acks.take(*read_answer(Bytes{102, 8}));
  acks.take(*read_answer(Bytes{105, 1}));  // SET-CONTROL: not waited for
  CHECK_FALSE(acks.complete());
  CHECK(acks.missing() == "parity, stop bits");
  acks.take(*read_answer(Bytes{103, 1}));
  acks.take(*read_answer(Bytes{104, 1}));
  CHECK(acks.complete());
  CHECK_FALSE(acks.refused());

  Acknowledgements other(asked);
  other.take(*read_answer(Bytes{101, 0x00, 0x00, 0x25, 0x80}));
  REQUIRE(other.refused());
  CHECK(*other.refused() == "the server set 9600 baud, not 62500");
  CHECK_FALSE(read_answer(Bytes{101, 0x00}));  // a rate needs four bytes
  CHECK_FALSE(read_answer(Bytes{7}));           // a client's command, not an answer
}

}  // namespace tiltgate::rfc2217
