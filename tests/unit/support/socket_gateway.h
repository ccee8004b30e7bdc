// A running gateway's control socket for the control tests (tests/unit/control/): one bus with
// one sensor at address 223 on a fake line, its event loop on its own thread, and beside it a
// second bus whose sensor is polled every 10 ms (counted in other_polls).
#pragma once

#include <boost/asio/co_spawn.hpp>
#include <boost/asio/detached.hpp>
#include <boost/asio/executor_work_guard.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/post.hpp>
#include <atomic>
#include <string>
#include <thread>
#include <vector>

#include "control/control_server.h"
#include "line_scheduling/bus_scheduler.h"
#include "unit/support/fake_bus.h"
#include "unit/support/scratch_dir.h"

namespace tiltgate::test {

using namespace std::chrono_literals;

inline BusConfig bus_on(std::string port) {
  BusConfig bus;
  bus.name = "line1";
  bus.port = std::move(port);
  bus.protocol = "fake";
  bus.baud = 19200;
  return bus;
}

struct SocketGateway {
  ScratchDir dir{"tiltgate-control"};
  std::string socket_path = dir.path("control.sock");
  boost::asio::io_context io;
  boost::asio::executor_work_guard<boost::asio::io_context::executor_type> work{io.get_executor()};
  FakeLine line{io.get_executor()};
  BusScheduler scheduler{io.get_executor(), line, "line1"};
  BusEvents events;
  std::unique_ptr<GatewaySensor> sensor = fake_sensor("boom", 1, 223, events, 10s);
  FakeLine other_line{io.get_executor()};
  BusScheduler other_scheduler{io.get_executor(), other_line, "line2"};
  BusEvents other_events;
  std::unique_ptr<GatewaySensor> other_sensor = fake_sensor("other", 2, 1, other_events, 10ms);
  std::atomic<int> other_polls{0};
  std::vector<LineRequest> sent;
  std::string port;
  ControlServer server;
  std::thread thread;

  explicit SocketGateway(std::string served_port = "/dev/ttyFAKE0")
      : port(std::move(served_port)),
        server{io.get_executor(), socket_path, {{bus_on(port), lent(scheduler)}}} {
    line.reply = [this](const LineRequest& request) {
      sent.push_back(LineRequest{request.bytes, request.address_bytes, nullptr, request.timeout,
                                 request.retries, request.settle, request.late_guard});
      return std::vector<std::uint8_t>{0xA0, 0xA1, 0xA2};
    };
    scheduler.add(*sensor);
    fake_driver(*other_sensor).on_poll = [this] { ++other_polls; };
    other_scheduler.add(*other_sensor);
    REQUIRE(server.start());
    boost::asio::co_spawn(io, scheduler.run(), boost::asio::detached);
    boost::asio::co_spawn(io, other_scheduler.run(), boost::asio::detached);
    thread = std::thread([this] { io.run(); });
  }
  ~SocketGateway() {
    boost::asio::post(io, [this] {
      server.stop();
      scheduler.stop();
      other_scheduler.stop();
      work.reset();
    });
    io.stop();
    thread.join();
  }
};

}  // namespace tiltgate::test
