// The per-sensor angle ring behind the status page's graph: bounded, oldest first, and
// overwriting the oldest once full; and the JSON and CSV the history endpoints serve from it.
#include <doctest/doctest.h>

#include <string>
#include <vector>

#include "status/angle_history.h"
#include "status/history_format.h"

using namespace tiltgate;

namespace {

std::vector<std::int64_t> times(const AngleRing& ring) {
  std::vector<std::int64_t> out;
  for (const AngleSample& s : ring.samples()) out.push_back(s.unix_ms);
  return out;
}

}  // namespace

TEST_CASE("history: the ring keeps its samples oldest first until it is full") {
  AngleRing ring(4);
  CHECK(ring.samples().empty());
  ring.push({1000, 1.5f, -2.25f});
  ring.push({2000, 1.75f, std::nullopt});
  CHECK(ring.size() == 2);
  CHECK(times(ring) == std::vector<std::int64_t>{1000, 2000});
  const auto samples = ring.samples();
  CHECK(samples[0].x == 1.5f);
  CHECK(samples[0].y == -2.25f);
  CHECK(samples[1].x == 1.75f);
  CHECK_FALSE(samples[1].y.has_value());
}

TEST_CASE("history: a full ring drops the oldest sample and never grows") {
  AngleRing ring(3);
  for (std::int64_t t = 1; t <= 7; ++t) ring.push({t, float(t), float(-t)});
  CHECK(ring.size() == 3);
  CHECK(ring.capacity() == 3);
  CHECK(times(ring) == std::vector<std::int64_t>{5, 6, 7});
  CHECK(ring.samples().back().y == -7.0f);
  // Exactly at the wrap point as well.
  AngleRing exact(3);
  for (std::int64_t t = 1; t <= 3; ++t) exact.push({t, 0.0f, 0.0f});
  CHECK(times(exact) == std::vector<std::int64_t>{1, 2, 3});
  exact.push({4, 0.0f, 0.0f});
  CHECK(times(exact) == std::vector<std::int64_t>{2, 3, 4});
}

TEST_CASE("history: a ring of capacity 0 keeps nothing") {
  AngleRing ring(0);
  ring.push({1, 1.0f, 1.0f});
  CHECK(ring.size() == 0);
  CHECK(ring.samples().empty());
}

TEST_CASE("history: JSON lists time and both angles, null for a missing angle") {
  CHECK(history_json({}) == "[]");
  CHECK(history_json({{1764638738250, 1.25f, -0.5f}, {1764638739250, std::nullopt, 2.0f}}) ==
        "[{\"t\":1764638738250,\"x\":1.25,\"y\":-0.5},"
        "{\"t\":1764638739250,\"x\":null,\"y\":2}]");
  // A float's shortest form, not its double expansion (0.1f is 0.10000000149011612).
  CHECK(history_json({{0, 0.1f, -12.345f}}) == "[{\"t\":0,\"x\":0.1,\"y\":-12.345}]");
}

TEST_CASE("history: a ring made with temperatures keeps them, and the JSON shows them") {
  AngleRing ring(2, true);
  CHECK(ring.keeps_temperatures());
  ring.push({1000, 1.5f, std::nullopt, 21.5f});
  ring.push({2000, 1.75f, std::nullopt, std::nullopt});  // stale: no temperature either
  ring.push({3000, 2.0f, std::nullopt, 22.25f});
  const auto samples = ring.samples();
  REQUIRE(samples.size() == 2);
  CHECK_FALSE(samples[0].temperature.has_value());
  CHECK(samples[1].temperature == 22.25f);
  CHECK(history_json(samples) == "[{\"t\":2000,\"x\":1.75,\"y\":null},"
                                 "{\"t\":3000,\"x\":2,\"y\":null,\"temperature\":22.25}]");
  // A ring without: a temperature given is not kept.
  AngleRing plain(2);
  CHECK_FALSE(plain.keeps_temperatures());
  plain.push({1000, 1.5f, std::nullopt, 21.5f});
  CHECK_FALSE(plain.samples()[0].temperature.has_value());
}

TEST_CASE("history: CSV has the header and ISO 8601 UTC times, an empty field when missing") {
  CHECK(history_csv({}) == "time_utc,unix_ms,x_deg,y_deg\r\n");
  CHECK(history_csv({{1764638738250, 1.25f, -0.5f}, {1764638739005, std::nullopt, std::nullopt}}) ==
        "time_utc,unix_ms,x_deg,y_deg\r\n"
        "2025-12-02T01:25:38.250Z,1764638738250,1.25,-0.5\r\n"
        "2025-12-02T01:25:39.005Z,1764638739005,,\r\n");
}

TEST_CASE("history: ISO 8601 times are UTC with milliseconds") {
  CHECK(iso8601_utc(0) == "1970-01-01T00:00:00.000Z");
  CHECK(iso8601_utc(951782400999) == "2000-02-29T00:00:00.999Z");
  CHECK(iso8601_utc(1798761599001) == "2026-12-31T23:59:59.001Z");
}

TEST_CASE("history: the CSV file name is the sensor's, with unusual characters replaced") {
  CHECK(history_csv_filename("tower-3_x.1") == "tower-3_x.1-history.csv");
  CHECK(history_csv_filename("a b\"/c") == "a_b__c-history.csv");
}
