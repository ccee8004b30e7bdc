// One session of the control socket (control/control_server.h): the answer to each message a
// commissioning command sends (control/control_protocol.h). After the versions agree and the
// command has its bus, its one `run` is the gateway's engine's work on that bus (CommandRunner,
// control/command_runner.h), whose events go back to the command as they happen while the
// session listens for the command's `stop`.
#pragma once

#include <boost/asio/awaitable.hpp>
#include <boost/asio/local/stream_protocol.hpp>
#include <boost/asio/streambuf.hpp>
#include <chrono>
#include <functional>
#include <string>

#include "audit/audit_record.h"
#include "control/command_runner.h"
#include "control/control_protocol.h"
#include "control/served_bus_line.h"

namespace tiltgate {

class ControlSession {
 public:
  // `find_bus`: the served bus on a tty or of a name, or null; `bus_list`: the buses, for a
  // refusal. `by`: the peer, for the audit trail. `runner`: the engine.
  struct Setup {
    std::function<const ServedBus*(const std::string&)> find_bus;
    std::function<std::string()> bus_list;
    WriteOrigin by;
    CommandRunner runner;
  };
  ControlSession(boost::asio::local::stream_protocol::socket& socket,
                 boost::asio::streambuf& input, Setup setup)
      : socket_(socket), input_(input), setup_(std::move(setup)) {}

  // How long the events of a run that ended may take to reach the command.
  static constexpr std::chrono::seconds kDrainTime{30};

  // The answer to one line, formatted; `done` turns true when the session must end after it.
  // A run's events are written before its answer (its exit line).
  boost::asio::awaitable<std::string> answer(const std::string& line, bool& done);

 private:
  // The first line must be the command's version, the gateway's own; otherwise the session
  // ends with the mismatch.
  std::string version(const control::CommandMessage* message, bool& done);
  std::string hello(const control::Hello& hello);
  boost::asio::awaitable<std::string> run(const control::Run& run);
  // Reads the command's lines while its run goes on (until `run_over`): `stop`, or the
  // command gone, stops it.
  boost::asio::awaitable<void> listen_for_stop(CommandStop& stop, const bool& run_over);

  boost::asio::local::stream_protocol::socket& socket_;
  boost::asio::streambuf& input_;
  Setup setup_;
  bool versions_agree_ = false;  // the command said the gateway's version first
  const ServedBus* bus_ = nullptr;  // the bus the command asked for
};

}  // namespace tiltgate
