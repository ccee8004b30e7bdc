// A BusScheduler on an io_context with the fake line and drivers of unit/support/fake_bus.h and
// the fake forwarding protocol of unit/support/fake_forwarding.h, for the scheduler's tests.
// Writes, forwarded requests and commands' transactions are queued from coroutines of their
// own, as Modbus connections and control sessions queue them; each sets its result when it is
// answered. The line records every framed request (forwarded ones and commands') in `sent`,
// and its event in `events` next to the drivers' polls and writes.
#pragma once

#include <boost/asio/co_spawn.hpp>
#include <boost/asio/detached.hpp>
#include <boost/asio/io_context.hpp>
#include <chrono>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "line_scheduling/bus_scheduler.h"
#include "line_scheduling/sensor_write.h"
#include "unit/support/fake_bus.h"
#include "unit/support/fake_forwarding.h"

namespace tiltgate::test {

// A write of `value` to the holding point of `sensor`'s map that sets `target`, planned as the
// router plans a one-register write (the built-in H6 map's settings are single words).
inline SensorWrite planned_write(GatewaySensor& sensor, WriteTarget target, double value) {
  const Point* point = nullptr;
  for (const Point& p : sensor.map.points())
    if (p.table == RegisterTable::holding && p.write == target) point = &p;
  std::vector<PlannedWrite> plan{{point, value, {std::uint16_t(value)}}};
  // An empty owner: the bench keeps the sensor alive.
  return SensorWrite(std::shared_ptr<GatewaySensor>(std::shared_ptr<GatewaySensor>(), &sensor),
                     std::move(plan), WriteOrigin{"modbus", "the bench"});
}

struct SchedulerBench {
  SchedulerBench() {
    scheduler.enable_forwarding(echo_forward);
    // Polls pass no framer, so only forwarded exchanges and commands' transactions reach this.
    // A command's request starts with 0xC0 and is answered 0xAC and its tag; a forwarded one
    // starts with its slave (30) and is echoed while the device answers.
    line.reply = [this](const LineRequest& request) {
      const bool command = request.bytes.at(0) == 0xC0;
      events.push_back((command ? "command " : "forward ") + std::to_string(request.bytes.at(1)));
      sent.push_back(LineRequest{request.bytes, request.address_bytes, nullptr, request.timeout,
                                 request.retries, request.settle});
      if (command) return std::vector<std::uint8_t>{0xAC, request.bytes.at(1)};
      return device_answers ? request.bytes : std::vector<std::uint8_t>{};
    };
  }
  ~SchedulerBench() {
    scheduler.stop();
    io.restart();
    io.run_for(std::chrono::milliseconds(100));  // lets the loop and any transaction in flight end
  }

  GatewaySensor& add(std::string name, std::uint32_t address,
                     std::chrono::milliseconds poll = std::chrono::milliseconds(100)) {
    sensors.push_back(fake_sensor(std::move(name), std::uint8_t(sensors.size() + 1), address,
                                  events, poll));
    scheduler.add(*sensors.back());
    return *sensors.back();
  }
  void start() { boost::asio::co_spawn(io, scheduler.run(), boost::asio::detached); }

  // The write of one setting of `sensor`.
  void write(GatewaySensor& sensor, WriteTarget target, double value,
             SteadyClock::time_point deadline, std::optional<WriteResult>& result) {
    spawn(result, [this, &sensor, target, value, deadline] {
      return scheduler.write(planned_write(sensor, target, value), deadline);
    });
  }
  // A forwarded request for slave 30 from `client`: PDU {tag, 0, 1}.
  void forward(std::uint8_t tag, SteadyClock::time_point deadline,
               std::optional<ForwardResult>& result, std::uint64_t client = 0) {
    spawn(result, [this, tag, deadline, client] {
      return scheduler.forward(30, std::vector<std::uint8_t>{tag, 0, 1}, deadline, client);
    });
  }
  // A command's transaction {0xC0, tag}, as a control session's, read by `framer`.
  void command(std::uint8_t tag, SteadyClock::time_point deadline,
               std::optional<CommandExchangeResult>& result) {
    spawn(result, [this, tag, deadline] {
      using std::chrono::milliseconds;
      LineRequest request{{0xC0, tag}, 0, &framer, milliseconds(7), 0, milliseconds(3)};
      return scheduler.exchange_for_command(std::move(request), deadline);
    });
  }

  boost::asio::io_context io;
  FakeLine line{io.get_executor()};
  BusScheduler scheduler{io.get_executor(), line, "bus"};
  BusEvents events;
  std::vector<std::unique_ptr<GatewaySensor>> sensors;
  std::vector<LineRequest> sent;  // forwarded requests and commands' as the line got them
  bool device_answers = true;     // of the forwarded requests
  AnyReply framer;                // the commands'

 private:
  // Queues what `queue` starts from a coroutine of its own, as a Modbus connection or a
  // control session would, and sets `result` when it is answered.
  template <class Result, class Queue>
  void spawn(std::optional<Result>& result, Queue queue) {
    boost::asio::co_spawn(
        io, [&result, queue]() -> boost::asio::awaitable<void> { result = co_await queue(); },
        boost::asio::detached);
  }
};

}  // namespace tiltgate::test
