// One session of the control socket (control/control_server.h): the answer to each message a
// commissioning command sends (control/control_protocol.h). Its transactions and reports go to
// the command's line on the bus it asked for (control/served_bus_line.h), which carries them
// between the gateway's polls and records what they changed.
#pragma once

#include <boost/asio/awaitable.hpp>
#include <boost/asio/local/stream_protocol.hpp>
#include <boost/asio/streambuf.hpp>
#include <functional>
#include <memory>
#include <string>

#include "audit/audit_record.h"
#include "control/control_protocol.h"
#include "control/served_bus_line.h"
#include "control/setting_claim.h"

namespace tiltgate {

class ControlSession {
 public:
  // `find_bus`: the served bus on a tty or of a name, or null; `bus_list`: the buses, for a
  // refusal. `by`: the peer, for the audit trail; `own_user`: it runs as the gateway's user.
  struct Setup {
    std::function<const ServedBus*(const std::string&)> find_bus;
    std::function<std::string()> bus_list;
    WriteOrigin by;
    bool own_user = false;
  };
  ControlSession(boost::asio::local::stream_protocol::socket& socket,
                 boost::asio::streambuf& input, Setup setup)
      : socket_(socket), input_(input), setup_(std::move(setup)) {}

  // The answer to one line, formatted; `done` turns true when the session must end after it.
  boost::asio::awaitable<std::string> answer(const std::string& line, bool& done);

 private:
  // The first line must be the command's version, the gateway's own; otherwise the session
  // ends with the mismatch.
  std::string version(const control::CommandMessage* message, bool& done);
  std::string act_for(const control::ActingFor& acting);
  std::string hello(const control::Hello& hello);
  boost::asio::awaitable<std::string> transact(const control::Transact& transact, bool& done);
  std::string setting(const control::SettingChanged& changed);

  boost::asio::local::stream_protocol::socket& socket_;
  boost::asio::streambuf& input_;
  Setup setup_;
  bool versions_agree_ = false;  // the command said the gateway's version first
  std::unique_ptr<ServedBusLine> line_;
  // How its latest transaction since its last `setting` report ended (control/setting_claim.h).
  control::CarriedOutcome carried_ = control::CarriedOutcome::none;
};

}  // namespace tiltgate
