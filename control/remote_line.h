// A commissioning command's Line through a running gateway's control socket
// (control/control_server.h): each transaction goes to the gateway, which sends it on its own
// bus between polls and relays what comes back, chunk by chunk, to this line, where the
// command's framer decides when the reply is whole. Drivers and commands cannot tell it from
// a tty of their own.
//
// The gateway's sensors must keep being polled on time meanwhile, so a command never holds
// that bus for long: each attempt is a turn of its own (control/attempt_turns.h).
#pragma once

#include <boost/asio/any_io_executor.hpp>
#include <boost/asio/local/stream_protocol.hpp>
#include <boost/asio/streambuf.hpp>
#include <chrono>
#include <memory>
#include <string>

#include "driver/expected.h"
#include "control/attempt_turns.h"
#include "driver/line.h"
#include "driver/write_target.h"
#include "control/control_protocol.h"

namespace tiltgate {

class RemoteLine final : public Line {
 public:
  struct ConnectError {
    // no_gateway: nothing listens on the socket (or it is not there); not_served: a gateway
    // listens but has no bus on the port; failed: it listens but the exchange went wrong.
    enum Kind { no_gateway, not_served, failed } kind;
    std::string message;
  };

  // Connects to the control socket at `socket_path` and asks for the bus on `port` (its tty,
  // or its name). Blocking, bounded by `timeout`: done before the command's event loop runs.
  static Expected<std::unique_ptr<RemoteLine>, ConnectError> connect(
      boost::asio::any_io_executor executor, const std::string& socket_path,
      const std::string& port, std::chrono::milliseconds timeout = std::chrono::seconds(3));

  boost::asio::awaitable<Expected<Done, LineError>> transact(LineRequest request) override;
  std::uint64_t generation() const override { return generation_; }
  bool is_open() const override { return socket_.is_open(); }
  int retries() const override { return defaults_.retries; }
  const std::string& name() const override { return name_; }
  const LineStats& stats() const override { return stats_; }
  const LineTiming& last_timing() const override { return timing_; }

  // What a request that leaves them to the bus gets (control/attempt_turns.h).
  void set_defaults(CommandLineDefaults defaults) { defaults_ = defaults; }


  // The bus the gateway granted: its name, protocol and baud.
  const control::BusGranted& bus() const { return bus_; }
  // Tells the gateway that a sensor on the bus moved from `from` to `to`; returns the
  // "bus/sensor" it followed, empty when it polls no sensor at `from`, or an error.
  Expected<std::string, std::string> follow(std::uint32_t from, std::uint32_t to);
  // Asks the gateway not to poll the sensor at `address` while the command moves it (see
  // control_protocol.h), or to poll it again. Returns the "bus/sensor" held, or empty.
  Expected<std::string, std::string> hold(std::uint32_t address);
  Expected<std::string, std::string> release(std::uint32_t address);
  // Tells the gateway how the sensor answered a setting (control_protocol.h), so that its
  // settings record follows an acknowledged one and its audit trail records it. Returns the
  // "bus/sensor" told, or empty, or an error.
  Expected<std::string, std::string> setting_changed(const control::SettingChanged& changed);
  // Asks the gateway to name `who` in its audit trail for this session's changes (`as`); an
  // error when it refuses.
  Expected<std::string, std::string> act_for(const std::string& who);
  // Closes the socket: a suspended transact() returns cancelled, as every later one does.
  void stop();

 private:
  RemoteLine(boost::asio::local::stream_protocol::socket socket, control::BusGranted bus);

  boost::asio::awaitable<bool> write_line(std::string line);
  // One message and its "ok" answer, synchronously (no transaction is running then).
  Expected<std::string, std::string> ask(const control::CommandMessage& message);
  // One attempt as one transaction of the gateway's (retries = 0).
  boost::asio::awaitable<Expected<Done, LineError>> attempt(const LineRequest& request);

  boost::asio::local::stream_protocol::socket socket_;
  boost::asio::streambuf input_;
  control::BusGranted bus_;
  std::string name_;
  CommandLineDefaults defaults_;
  std::uint64_t generation_ = 1;
  bool stopped_ = false;
  LineStats stats_;
  LineTiming timing_;
};

}  // namespace tiltgate
