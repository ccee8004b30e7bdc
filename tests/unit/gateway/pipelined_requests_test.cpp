// Requests a client sends back to back without waiting (pipelined), through the gateway's real
// server, router and reader: every one is answered, in the order sent, whether the reader
// answers it at once (a read, an exception) or it waits for the bus (a write) in between.
#include <doctest/doctest.h>

#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <cstdint>
#include <vector>

#include "e2e/support/http_client.h"  // connect_to: a loopback socket with a read time limit
#include "unit/support/served_plant.h"

using namespace tiltgate;
using namespace tiltgate::test;
using namespace std::chrono_literals;

namespace {

using Bytes = std::vector<std::uint8_t>;

Bytes modbus_request(std::uint16_t transaction, std::uint8_t function, std::uint16_t address,
                     std::uint16_t value) {
  return {std::uint8_t(transaction >> 8), std::uint8_t(transaction), 0, 0, 0, 6, 1, function,
          std::uint8_t(address >> 8), std::uint8_t(address), std::uint8_t(value >> 8),
          std::uint8_t(value)};
}

// The replies to `count` requests, read whole by their MBAP lengths (until a read times out).
std::vector<Bytes> replies(int fd, std::size_t count) {
  Bytes stream;
  std::vector<Bytes> whole;
  std::uint8_t buffer[4096];
  while (whole.size() < count) {
    const ssize_t n = ::recv(fd, buffer, sizeof buffer, 0);
    if (n <= 0) break;
    stream.insert(stream.end(), buffer, buffer + n);
    while (stream.size() >= 7) {
      const std::size_t size = 6u + ((stream[4] << 8) | stream[5]);  // MBAP header + length
      if (stream.size() < size) break;
      whole.emplace_back(stream.begin(), stream.begin() + std::ptrdiff_t(size));
      stream.erase(stream.begin(), stream.begin() + std::ptrdiff_t(size));
    }
  }
  return whole;
}

struct OneSensorPlant : ServedPlant {
  OneSensorPlant() : ServedPlant(1, true) {
    sensors.push_back(std::shared_ptr<GatewaySensor>(fake_sensor("s1", 1, 1, events, 100ms)));
    scheduler.add(sensors.back());
    router.add(sensors.back());
    serve();
  }
};

}  // namespace

TEST_CASE("pipelined reads, exceptions and a write are all answered, in the order sent") {
  OneSensorPlant plant;
  const int fd = connect_to(plant.port, 5);

  // 60 requests in one send: reads of 4 and 10 input registers, a read past the map (02),
  // and a write to the filter setting (holding 0) in the middle, which waits for the bus.
  Bytes stream;
  std::vector<std::uint8_t> functions;
  for (std::uint16_t t = 1; t <= 60; ++t) {
    Bytes one = t == 30      ? modbus_request(t, 0x06, 0, 2)
                : t % 7 == 0 ? modbus_request(t, 0x04, 9000, 10)
                             : modbus_request(t, 0x04, 0, t % 2 == 0 ? 4 : 10);
    functions.push_back(one[7]);
    stream.insert(stream.end(), one.begin(), one.end());
  }
  REQUIRE(::send(fd, stream.data(), stream.size(), 0) == ssize_t(stream.size()));

  const std::vector<Bytes> got = replies(fd, 60);
  ::close(fd);
  REQUIRE(got.size() == 60);
  for (std::uint16_t t = 1; t <= 60; ++t) {
    const Bytes& reply = got[t - 1];
    INFO("transaction ", t);
    CHECK(((reply[0] << 8) | reply[1]) == t);  // in the order sent
    if (t % 7 == 0 && t != 30) {
      CHECK(reply[7] == (0x80 | 0x04));
      CHECK(reply[8] == 0x02);
    } else {
      CHECK(reply[7] == functions[t - 1]);
    }
  }
  CHECK(plant.server->stats().requests == 60);
}

