// How `info` and `watch` show a sensor: info lines, table rows, the CSV log.
#include <doctest/doctest.h>

#include <cmath>
#include <sstream>
#include <vector>

#include "commission/reading_format.h"

using namespace tiltgate;
using namespace std::chrono_literals;

namespace {

std::vector<std::string> fields(const std::string& line, char separator) {
  std::vector<std::string> out;
  std::string field;
  std::istringstream in(line);
  while (std::getline(in, field, separator)) out.push_back(field);
  if (!line.empty() && line.back() == separator) out.emplace_back();
  return out;
}

std::vector<std::string> words(const std::string& line) {
  std::vector<std::string> out;
  std::istringstream in(line);
  for (std::string w; in >> w;) out.push_back(w);
  return out;
}

SensorState answering(double x, double y, SteadyClock::time_point taken) {
  SensorState state;
  state.online = true;
  state.identity_known = true;
  state.serial = "9600223";
  state.firmware = "Rev A.8";
  Reading reading;
  reading.angle_x = x;
  reading.angle_y = y;
  reading.taken = taken;
  state.reading = reading;
  return state;
}

// 2026-12-01T20:40:01.123Z
const std::chrono::system_clock::time_point kTime{std::chrono::milliseconds(1796157601123)};

}  // namespace

TEST_CASE("log times are ISO 8601 UTC with milliseconds") {
  CHECK(iso8601_utc_ms(kTime) == "2026-12-01T20:40:01.123Z");
  CHECK(iso8601_utc_ms(kTime + 877ms) == "2026-12-01T20:40:02.000Z");
  CHECK(iso8601_utc_ms(std::chrono::system_clock::time_point{5ms}) == "1970-01-01T00:00:00.005Z");
}

TEST_CASE("a CSV line has the time, address, serial, angles, tilt and status, in the header's order") {
  CHECK(csv_header() == "time,address,serial,x_deg,y_deg,tilt_deg,status\n");
  const auto now = SteadyClock::now();
  const WatchRow s = snapshot_of(223, answering(3.0, -4.0, now), now, std::nullopt);
  const std::string line = csv_line(kTime, s);
  REQUIRE(line.back() == '\n');
  const auto f = fields(line.substr(0, line.size() - 1), ',');
  REQUIRE(f.size() == 7);
  CHECK(f[0] == "2026-12-01T20:40:01.123Z");
  CHECK(f[1] == "223");
  CHECK(f[2] == "9600223");
  CHECK(std::stod(f[3]) == doctest::Approx(3.0));
  CHECK(std::stod(f[4]) == doctest::Approx(-4.0));
  CHECK(std::stod(f[5]) == doctest::Approx(4.9942).epsilon(0.00002));  // not sqrt(9 + 16) = 5
  CHECK(f[6] == "ok");
}

TEST_CASE("a CSV line for a silent sensor leaves the angles empty, not the last reading's") {
  const auto now = SteadyClock::now();
  SensorState state = answering(3.0, -4.0, now - 2s);
  state.online = false;
  const std::string line = csv_line(kTime, snapshot_of(7, state, now, std::nullopt));
  CHECK(line == "2026-12-01T20:40:01.123Z,7,9600223,,,,no-reply\n");
}

TEST_CASE("a CSV field with a comma or quote is quoted") {
  const auto now = SteadyClock::now();
  SensorState state = answering(1.0, NAN, now);
  state.serial = "A,\"B\"";
  const std::string line = csv_line(kTime, snapshot_of(1, state, now, std::nullopt));
  CHECK(line == "2026-12-01T20:40:01.123Z,1,\"A,\"\"B\"\"\",1.0000,,1.0000,ok\n");
}

TEST_CASE("a watch row lines up with the header: address, serial, x, y, tilt, status, age, rate") {
  const auto now = SteadyClock::now();
  const auto header = words(watch_header());
  REQUIRE(header.size() == 8);
  CHECK(header[0] == "ADDRESS");
  CHECK(header[5] == "STATUS");
  CHECK(watch_row(snapshot_of(5, answering(1.5, -2.25, now - 40ms), now, 9.5)).size() ==
        watch_header().size());

  const auto row = words(watch_row(snapshot_of(5, answering(1.5, -2.25, now - 40ms), now, 9.5)));
  REQUIRE(row.size() == 8);
  CHECK(row[0] == "5");
  CHECK(row[1] == "9600223");
  CHECK(row[2] == "1.500");
  CHECK(row[3] == "-2.250");
  CHECK(row[4] == "2.703");
  CHECK(row[5] == "ok");
  CHECK(row[6] == "40");
  CHECK(row[7] == "9.5");
}

TEST_CASE("a watch row shows dashes for what a sensor has not told, and no-reply when silent") {
  SensorState never;
  const auto row = words(watch_row(snapshot_of(224, never, SteadyClock::now(), std::nullopt)));
  CHECK(row == std::vector<std::string>{"224", "-", "-", "-", "-", "no-reply", "-", "-"});

  const auto now = SteadyClock::now();
  const auto single = words(watch_row(snapshot_of(1, answering(-30.5, NAN, now), now, 1.0)));
  REQUIRE(single.size() == 8);
  CHECK(single[3] == "-");
  CHECK(single[4] == "30.500");  // one axis: the tilt is its magnitude
}

TEST_CASE("the reading rate counts new readings after the first over the time since it") {
  ReadingRate rate;
  const auto start = SteadyClock::now();
  SensorState state = answering(1.0, 1.0, start);
  rate.update(state);
  CHECK_FALSE(rate.per_second());
  rate.update(state);  // the same reading again: a failed poll
  CHECK_FALSE(rate.per_second());
  for (int i = 1; i <= 4; ++i) {
    state.reading->taken = start + i * 250ms;
    ++state.sample_seq;
    rate.update(state);
  }
  REQUIRE(rate.per_second());
  CHECK(*rate.per_second() == doctest::Approx(4.0));
}

TEST_CASE("info shows each fact on its own line, with a dash for a lock level the protocol lacks") {
  SensorState state = answering(1.5, -2.25, SteadyClock::now());
  const std::string text = sensor_info_text(223, "h6", state);
  CHECK(text ==
        "address:    223\n"
        "model:      h6\n"
        "serial:     9600223\n"
        "firmware:   Rev A.8\n"
        "lock level: -\n"
        "angle x:    1.500 deg\n"
        "angle y:    -2.250 deg\n"
        "tilt:       2.703 deg\n");
  state.protection_level = 0;
  CHECK(sensor_info_text(223, "h6", state).find("lock level: 0\n") != std::string::npos);
}

TEST_CASE("a freshly zeroed sensor shows 0.000, not -0.000, in info, watch rows and the CSV") {
  const SensorState state = answering(-0.0002, 0.0001, SteadyClock::now());
  const std::string text = sensor_info_text(7, "h6", state);
  CHECK(text.find("angle x:    0.000 deg\n") != std::string::npos);
  CHECK(text.find("-0.000") == std::string::npos);
  const WatchRow row = snapshot_of(7, state, SteadyClock::now(), 1.0);
  CHECK(words(watch_row(row)).at(2) == "0.000");
  CHECK(fields(csv_line(kTime, snapshot_of(7, answering(-0.00004, 0, SteadyClock::now()),
                                           SteadyClock::now(), 1.0)),
               ',')
            .at(3) == "0.0000");
  // A real negative reading keeps its sign.
  CHECK(sensor_info_text(7, "h6", answering(-0.0006, 0, SteadyClock::now())).find("angle x:    -0.001 deg") !=
        std::string::npos);
}
