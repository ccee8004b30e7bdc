#include "rieker/simulator.h"

#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <limits>

#include "driver/simulator_command.h"

namespace tiltgate::rieker {
namespace {

constexpr unsigned kBitsPerByte = 10;  // 8N1: start + 8 data + stop

}  // namespace

RiekerSimulator::RiekerSimulator(boost::asio::io_context& io, RiekerSimulatorOptions options)
    : SimulatedBus(io, options, kBitsPerByte), options_(std::move(options)) {
  sensors_.reserve(options_.sensors.size());
  for (const auto& sensor : options_.sensors) sensors_.emplace_back(sensor);
}

SimulatedSensor* RiekerSimulator::sensor_by_address(std::uint16_t address) {
  for (auto& sensor : sensors_) {
    if (sensor.address() == address) return &sensor;
  }
  return nullptr;
}

SimulatorCounters RiekerSimulator::counters() const {
  SimulatorCounters own;
  own.crc_errors = crc_errors_;
  return with_bus_counters(own);
}

namespace {

constexpr int kAlways = std::numeric_limits<int>::max();

// "silent", "garbage", "busy" and "answer" (every fault of these and "late" undone): a
// fault of every reply from now on, or none.
Expected<Done, std::string> set_fault(SimulatedSensor& sensor, const SimulatorCommand& command) {
  SensorFaults& faults = sensor.faults();
  if (command.verb == "late") {
    if (command.values.size() != 1 || command.values[0] < 0 || command.values[0] > 60000 ||
        command.values[0] != std::floor(command.values[0]))
      return Unexpected{std::string("late takes a whole number of milliseconds, 0..60000")};
    faults.reply_delay = std::chrono::milliseconds(int(command.values[0]));
    return Done{};
  }
  if (!command.values.empty())
    return Unexpected{fmt::format("{} takes only an address", command.verb)};
  if (command.verb == "answer") {
    faults.silent = faults.corrupt_crc = faults.busy = 0;
    faults.reply_delay = std::chrono::milliseconds(0);
  } else if (command.verb == "silent") {
    faults.silent = kAlways;
  } else if (command.verb == "garbage") {
    faults.corrupt_crc = kAlways;
  } else {
    faults.busy = kAlways;
  }
  return Done{};
}

}  // namespace

Expected<Done, std::string> RiekerSimulator::command(std::string_view line) {
  auto parsed = parse_simulator_command(line);
  if (!parsed) return Unexpected{parsed.error()};
  if (auto plugged = plug_command(*parsed)) return *plugged;
  const std::string& verb = parsed->verb;
  const bool known = verb == "angle" || verb == "silent" || verb == "answer" ||
                     verb == "garbage" || verb == "late" || verb == "busy" || verb == "serial";
  if (!known) {
    return Unexpected{"unknown command \"" + verb +
                      "\" (try: angle ADDRESS X [Y], silent ADDRESS, garbage ADDRESS, late "
                      "ADDRESS MS, busy ADDRESS, answer ADDRESS, serial ADDRESS NUMBER, unplug MASTER, "
                      "replug MASTER)"};
  }
  SimulatedSensor* sensor =
      parsed->address > 0xFFFF ? nullptr : sensor_by_address(std::uint16_t(parsed->address));
  if (sensor == nullptr) return Unexpected{fmt::format("no sensor at address {}", parsed->address)};
  if (verb == "serial") {
    // Another sensor swapped in at the address (a field swap: `silent` first, then `answer`).
    const std::vector<double>& number = parsed->values;
    if (number.size() != 1 || number[0] < 0 || number[0] > 9'999'999'999.0 ||
        number[0] != std::floor(number[0]))
      return Unexpected{std::string("serial takes one whole number of at most 10 digits")};
    sensor->set_serial(fmt::format("{}", std::uint64_t(number[0])));
    return Done{};
  }
  if (verb != "angle") return set_fault(*sensor, *parsed);
  const std::size_t axes = sensor->model() == Model::h6 ? 2 : 1;
  const std::vector<double>& angles = parsed->values;
  if (angles.empty() || angles.size() > axes) {
    return Unexpected{fmt::format("the sensor at address {} takes {} angle(s)", parsed->address,
                                  axes == 2 ? "1 or 2" : "1")};
  }
  sensor->set_angles(angles[0], angles.size() > 1 ? angles[1] : 0.0);
  return Done{};
}

void RiekerSimulator::receive(std::span<const std::uint8_t> bytes) {
  const std::uint64_t crc_errors_before = parser_.counters().crc_errors;
  parser_.feed(bytes);
  crc_errors_ += parser_.counters().crc_errors - crc_errors_before;
  while (auto request = parser_.next()) dispatch(*request);
  const auto damaged = parser_.take_crc_failure();
  if (!damaged || !options_.nak_on_crc_failure) return;
  for (auto& sensor : sensors_) {
    if (auto reply = sensor.handle_crc_failure(*damaged)) send_reply(encode(*reply));
  }
}

// Two sensors that answer one request (two at one address, or a broadcast query to several)
// collide: the first reply stands for them, its CRC broken.
void RiekerSimulator::dispatch(const Frame& request) {
  count_request();
  const SimTime at = elapsed();
  Answers answers;
  for (auto& sensor : sensors_) {
    if (auto bytes = sensor.respond(request, at))
      answers.add(std::move(*bytes), sensor.reply_delay(request.function));
  }
  send(std::move(answers));
}

}  // namespace tiltgate::rieker
