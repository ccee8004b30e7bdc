// The commissioning commands on a bus of two Rieker models, an H6 at 223 and an H4360 at 101,
// with no --model: each sensor is polled as the model it measures as, and says which that was.
// A refusal (a NAK) is reported with its code and the manual's meaning, never as "no reply".
#include <doctest/doctest.h>

#include <fstream>
#include <sstream>

#include "e2e/support/gateway_process.h"
#include "e2e/support/output_checks.h"
#include "e2e/support/simulator_process.h"

using namespace tiltgate::test;

namespace {

const std::string kNak2 = "NAK 2 (function not valid for this sensor or mode)";

SimulatorProcess mixed_bus() { return SimulatorProcess({"rieker", "--sensors", "h6:223,h4360:101"}); }

CommandResult on_bus(const SimulatorProcess& sim, std::vector<std::string> args) {
  args.insert(args.begin() + 1, {"--port", sim.tty()});
  return run_tiltgate(args);
}

// The whitespace-separated words of the line of `out` that starts with `first`.
std::vector<std::string> row_of(const std::string& out, const std::string& first) {
  std::istringstream in(out);
  for (std::string line; std::getline(in, line);) {
    std::istringstream words(line);
    std::vector<std::string> row;
    for (std::string w; words >> w;) row.push_back(w);
    if (!row.empty() && row.front() == first) return row;
  }
  return {};
}

}  // namespace

TEST_CASE("info without --model reads an H4360 as an H4360 and an H6 as an H6, and says so") {
  auto sim = mixed_bus();
  const auto h4360 = on_bus(sim, {"info", "--address", "101"});
  INFO(h4360.out << h4360.err);
  CHECK(h4360.exit_code == 0);
  CHECK(has_line(h4360.out, "model:      h4360"));
  CHECK(has_line(h4360.out, "serial:     9600101"));
  CHECK(has_line(h4360.out, "angle y:    -"));
  CHECK_FALSE(has(h4360.out, "no reply"));
  CHECK(has(h4360.err, "address 101: model h4360 (detected"));

  const auto h6 = on_bus(sim, {"info", "--address", "223"});
  INFO(h6.out << h6.err);
  CHECK(h6.exit_code == 0);
  CHECK(has_line(h6.out, "model:      h6"));
  CHECK(has(h6.err, "address 223: model h6 (detected)"));
}

TEST_CASE("info with a --model the sensor refuses reports the NAK and its meaning, not no reply") {
  auto sim = mixed_bus();
  const auto info = on_bus(sim, {"info", "--model", "h6", "--address", "101"});
  INFO(info.out << info.err);
  CHECK(info.exit_code == 1);
  CHECK(has_line(info.out, "status:     refused: " + kNak2));
  CHECK_FALSE(has(info.out + info.err, "no reply"));
  CHECK(has(info.err, "refused the measurement as model h6: " + kNak2));
  // --model decides, and the check says what the sensor measures as.
  CHECK(has(info.err, "address 101 measures as model h4360, not as the h6 that --model names"));
}

TEST_CASE("set without --model moves an H4360 and reads it back as an H4360") {
  auto sim = mixed_bus();
  const auto set = on_bus(sim, {"set", "--address", "101", "address", "105"});
  INFO(set.out << set.err);
  CHECK(set.exit_code == 0);
  CHECK(has_line(set.out, "the sensor now answers at address 105"));
  CHECK(has_line(set.out, "address:    105"));
  CHECK(has_line(set.out, "model:      h4360"));
  CHECK_FALSE(has(set.err, "no reply"));

  const auto filter = on_bus(sim, {"set", "--address", "105", "filter", "3"});
  INFO(filter.out << filter.err);
  CHECK(filter.exit_code == 0);
  CHECK(has_line(filter.out, "filter 3 at address 105: acknowledged"));
  CHECK(has_line(filter.out, "filter:     3"));
}

TEST_CASE("set whose read-back the sensor refuses says it refused, with the NAK, not no reply") {
  auto sim = mixed_bus();
  const auto set = on_bus(sim, {"set", "--model", "h6", "--address", "101", "filter", "3"});
  INFO(set.out << set.err);
  CHECK(set.exit_code == 1);
  CHECK(has_line(set.out, "filter 3 at address 101: acknowledged"));
  CHECK(has_line(set.out, "status:     refused: " + kNak2));
  CHECK(has(set.err, "the change was acknowledged, but reading back: address 101 answered, but "
                     "refused the measurement as model h6: " + kNak2));
  CHECK_FALSE(has(set.out + set.err, "no reply"));
  CHECK_FALSE(has(set.err, "hint:"));  // the wiring is fine: the sensor answered
}

TEST_CASE("watch without --model shows the H4360's angle, and logs it") {
  auto sim = mixed_bus();
  const std::string log = (sim.dir().path() / "angles.csv").string();
  const auto watch =
      on_bus(sim, {"watch", "--address", "101,223", "--count", "2", "--interval", "50", "--log", log});
  INFO(watch.out << watch.err);
  CHECK(watch.exit_code == 0);
  const auto h4360 = row_of(watch.out, "101");
  REQUIRE(h4360.size() == 8);
  CHECK(h4360[2] != "-");  // X
  CHECK(h4360[3] == "-");  // no Y on one axis
  CHECK(h4360[5] == "ok");
  CHECK(row_of(watch.out, "223").at(5) == "ok");

  std::ifstream in(log);
  std::string line;
  int rows_101 = 0;
  while (std::getline(in, line)) {
    if (line.find(",101,") == std::string::npos) continue;
    ++rows_101;
    CHECK_MESSAGE(line.find(",101,9600101,,") == std::string::npos, line);  // X is logged
    CHECK(line.substr(line.rfind(',') + 1) == "ok");
  }
  CHECK(rows_101 == 2);
}

TEST_CASE("watch with a --model the sensor refuses shows refused and the NAK, not ok") {
  auto sim = mixed_bus();
  const auto watch =
      on_bus(sim, {"watch", "--model", "h6", "--address", "101", "--count", "1", "--interval", "50"});
  INFO(watch.out << watch.err);
  CHECK(watch.exit_code == 0);
  CHECK(row_of(watch.out, "101").at(5) == "refused");
  CHECK(has(watch.err, "refused the measurement as model h6: " + kNak2));
}
