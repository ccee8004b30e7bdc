// The control socket ([server] control_socket): a local Unix socket through which commissioning
// commands (`tiltgate scan|info|set|raw|watch --via-gateway`) use a running gateway's buses, so
// that commissioning one sensor never stops the PLC seeing the others.
//
// A command asks for the bus on its tty, then has the gateway run it there
// (control/control_protocol.h): the gateway's commissioning engine does the command's work on
// that bus between polls (each transaction a turn of the line's spare time, BusScheduler::
// exchange_for_command) and sends its events back as they happen, which the command renders
// as it does a run on its own tty. A sensor it moves is polled at its new address from then on.
//
// Anyone who can connect can talk to the sensors and change their settings, whatever
// [server] writes says: the socket file is made mode 0660, for its owner and group only, from
// the moment it exists. Who connected (SO_PEERCRED) is named in the log line of a sensor it
// moved, and in the audit trail of what it changed.
#pragma once

#include <boost/asio/any_io_executor.hpp>
#include <boost/asio/awaitable.hpp>
#include <boost/asio/local/stream_protocol.hpp>
#include <memory>
#include <string>
#include <vector>

#include "config/config.h"
#include "driver/expected.h"
#include "driver/family.h"
#include "control/command_runner.h"
#include "control/served_bus_line.h"

namespace tiltgate {

class ControlServer {
 public:
  using ServedBus = tiltgate::ServedBus;

  // `runner`: what a command's `run` does on its bus (the commissioning engine).
  ControlServer(boost::asio::any_io_executor executor, std::string path,
                std::vector<ServedBus> buses, CommandRunner runner);
  ~ControlServer();
  ControlServer(const ControlServer&) = delete;
  ControlServer& operator=(const ControlServer&) = delete;

  // Creates the socket's folder if missing, replaces a stale socket file (one nobody listens
  // on, left by a gateway that was killed) but not a live one, and listens.
  Expected<Done, std::string> start();
  // Stops accepting, ends the sessions and removes the socket file.
  void stop();

  const std::string& path() const { return path_; }
  bool listening() const { return listening_; }
  // Stopped, and its accept loop and every session have ended: nothing refers to it any more,
  // so a reload that replaced it may free it (and the buses it held).
  bool finished() const { return !listening_ && coroutines_ == 0; }

  // Sessions at once; more are told so and closed. Commissioning is one engineer at a time.
  static constexpr std::size_t kMaxSessions = 8;

 private:
  void bind_for_owner_and_group(boost::system::error_code& error);
  boost::asio::awaitable<void> accept_loop();
  boost::asio::awaitable<void> session(boost::asio::local::stream_protocol::socket socket);
  // Runs `work` on the executor, counted in coroutines_ until it ends.
  void spawn(boost::asio::awaitable<void> work);
  ServedBus* find_bus(const std::string& port_or_name);
  std::string bus_list() const;

  boost::asio::any_io_executor executor_;
  std::string path_;
  std::vector<ServedBus> buses_;
  CommandRunner runner_;
  boost::asio::local::stream_protocol::acceptor acceptor_;
  std::vector<std::weak_ptr<boost::asio::local::stream_protocol::socket>> sessions_;
  bool listening_ = false;
  std::size_t coroutines_ = 0;  // the accept loop and the sessions running
};

}  // namespace tiltgate
