// Whom a new Modbus TCP connection displaces when the server is full (doors/connection_admission.h).
#include <doctest/doctest.h>

#include <vector>

#include "doors/connection_admission.h"

using namespace tiltgate;

namespace {

using Clock = std::chrono::steady_clock;
const Clock::time_point t0{};

OpenConnection idle(std::string_view address, int since_s) {
  return {address, true, t0 + std::chrono::seconds(since_s)};
}
OpenConnection busy(std::string_view address, int since_s) {
  return {address, false, t0 + std::chrono::seconds(since_s)};
}

}  // namespace

TEST_CASE("admission: below both limits a connection is admitted and replaces nothing") {
  const std::vector<OpenConnection> open{idle("10.0.0.1", 1)};
  const Admission a = admit_connection(open, "10.0.0.2", {2, 8});
  CHECK(a.admitted);
  CHECK_FALSE(a.replaced.has_value());
  CHECK(a.limit == AdmissionLimit::none);
}

TEST_CASE("admission: at max_clients the connection idle longest is replaced, never a busy one") {
  // The busy one has been "idle" since longest, but it is mid-request: it is never chosen.
  const std::vector<OpenConnection> open{busy("10.0.0.1", 0), idle("10.0.0.2", 5),
                                         idle("10.0.0.3", 2), idle("10.0.0.4", 9)};
  const Admission a = admit_connection(open, "10.0.0.9", {4, 8});
  CHECK(a.admitted);
  REQUIRE(a.replaced.has_value());
  CHECK(*a.replaced == 2);
  CHECK(a.limit == AdmissionLimit::max_clients);
}

TEST_CASE("admission: at max_clients with none idle the connection is refused") {
  const std::vector<OpenConnection> open{busy("10.0.0.1", 0), busy("10.0.0.2", 1)};
  const Admission a = admit_connection(open, "10.0.0.9", {2, 8});
  CHECK_FALSE(a.admitted);
  CHECK_FALSE(a.replaced.has_value());
  CHECK(a.limit == AdmissionLimit::max_clients);
}

TEST_CASE("admission: an address at its cap replaces its own idle connection, not another's") {
  // Another address's connection is idle longer, and the server is not full.
  const std::vector<OpenConnection> open{idle("10.0.0.7", 0), idle("10.0.0.1", 4),
                                         idle("10.0.0.1", 3), busy("10.0.0.1", 1)};
  const Admission a = admit_connection(open, "10.0.0.1", {32, 3});
  CHECK(a.admitted);
  REQUIRE(a.replaced.has_value());
  CHECK(*a.replaced == 2);
  CHECK(a.limit == AdmissionLimit::max_clients_per_host);
}

TEST_CASE("admission: an address at its cap with none of its own idle is refused") {
  const std::vector<OpenConnection> open{idle("10.0.0.7", 0), busy("10.0.0.1", 1),
                                         busy("10.0.0.1", 2)};
  const Admission a = admit_connection(open, "10.0.0.1", {32, 2});
  CHECK_FALSE(a.admitted);
  CHECK(a.limit == AdmissionLimit::max_clients_per_host);
  // Another address still gets in.
  CHECK(admit_connection(open, "10.0.0.8", {32, 2}).admitted);
}

TEST_CASE("admission: a kept-alive connection between requests gives way before one idle longer") {
  // 10.0.0.1 has waited longest for a first request; 10.0.0.3, served and kept alive, goes first.
  OpenConnection kept_alive = idle("10.0.0.3", 7);
  kept_alive.gives_way_first = true;
  const std::vector<OpenConnection> open{idle("10.0.0.1", 0), idle("10.0.0.2", 3), kept_alive};
  const Admission a = admit_connection(open, "10.0.0.9", {3, 8});
  CHECK(a.admitted);
  REQUIRE(a.replaced.has_value());
  CHECK(*a.replaced == 2);
}
