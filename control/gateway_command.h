// A commissioning command run by a running gateway, from the command line's side of the
// control socket (control/control_server.h): the command asks for the bus on its tty, sends
// its request, and hands on each event the gateway's engine reports until the gateway says the
// command's exit code (control/control_protocol.h). The command renders the events as it does
// those of a run on its own tty; it never touches the bus itself.
#pragma once

#include <boost/asio/any_io_executor.hpp>
#include <boost/asio/awaitable.hpp>
#include <boost/asio/local/stream_protocol.hpp>
#include <boost/asio/streambuf.hpp>
#include <chrono>
#include <functional>
#include <memory>
#include <string>

#include "control/control_protocol.h"
#include "driver/expected.h"

namespace tiltgate {

class GatewayCommand {
 public:
  struct ConnectError {
    // no_gateway: nothing listens on the socket (or it is not there); not_served: a gateway
    // listens but has no bus on the port; failed: it listens but the exchange went wrong.
    enum Kind { no_gateway, not_served, failed } kind;
    std::string message;
  };

  // Connects to the control socket at `socket_path` and asks for the bus on `port` (its tty,
  // or its name). Blocking, bounded by `timeout`: done before the command's event loop runs.
  static Expected<std::unique_ptr<GatewayCommand>, ConnectError> connect(
      boost::asio::any_io_executor executor, const std::string& socket_path,
      const std::string& port, std::chrono::milliseconds timeout = std::chrono::seconds(3));

  // The bus the gateway granted: its name, protocol and baud.
  const control::BusGranted& bus() const { return bus_; }

  // Sends `request` (one JSON object) and gives each event's JSON to `on_event` as it comes.
  // The command's exit code as the gateway said it, or why the session broke off.
  boost::asio::awaitable<Expected<int, std::string>> run(
      std::string request, std::function<void(const std::string&)> on_event);
  // The engineer pressed Ctrl-C: the gateway is asked to stop the run, which then ends with its
  // exit line as usual. Asked a second time, the command stops waiting: the socket closes.
  void stop();

 private:
  GatewayCommand(boost::asio::local::stream_protocol::socket socket, std::string socket_path,
                 control::BusGranted bus);

  boost::asio::local::stream_protocol::socket socket_;
  std::string socket_path_;
  boost::asio::streambuf input_{control::kMaxEventLine};
  control::BusGranted bus_;
  std::string stop_line_;  // kept while it is written
  int stops_ = 0;
};

}  // namespace tiltgate
