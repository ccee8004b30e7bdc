#include "control/control_session.h"

#include <boost/asio/co_spawn.hpp>
#include <boost/asio/read_until.hpp>
#include <boost/asio/redirect_error.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/asio/use_awaitable.hpp>
#include <fmt/format.h>
#include <istream>
#include <memory>
#include <spdlog/spdlog.h>

#include "control/event_writer.h"

namespace tiltgate {

namespace asio = boost::asio;

namespace {

std::string formatted(const control::GatewayMessage& message) { return control::format(message); }

}  // namespace

std::string ControlSession::version(const control::CommandMessage* message, bool& done) {
  const auto* said = message ? std::get_if<control::Version>(message) : nullptr;
  if (said != nullptr && said->protocol == control::kProtocolVersion) {
    versions_agree_ = true;
    return formatted(control::Version{control::kProtocolVersion, TILTGATE_VERSION});
  }
  done = true;
  return control::version_mismatch(TILTGATE_VERSION, said ? std::optional(*said) : std::nullopt);
}

std::string ControlSession::hello(const control::Hello& hello) {
  const ServedBus* bus = setup_.find_bus(hello.port);
  if (bus == nullptr)
    return formatted(control::Refused{fmt::format("the gateway has no bus on {} (its buses: {})",
                                                  hello.port, setup_.bus_list())});
  bus_ = bus;
  return formatted(control::BusGranted{bus->config.name, bus->config.protocol, bus->config.baud});
}

asio::awaitable<void> ControlSession::listen_for_stop(CommandStop& stop, const bool& run_over) {
  while (!run_over) {
    boost::system::error_code ec;
    co_await asio::async_read_until(socket_, input_, '\n',
                                    asio::redirect_error(asio::use_awaitable, ec));
    // Cancelled: the run ended first. Anything else: the command is gone, or broke the
    // protocol (a line too long); either way nobody waits for the rest of the run.
    if (ec == asio::error::operation_aborted) co_return;
    if (ec) {
      stop.request();
      co_return;
    }
    std::string line;
    std::istream stream(&input_);
    std::getline(stream, line);
    const auto message = control::parse_command(line);
    if (!message || std::holds_alternative<control::Stop>(*message)) {
      stop.request();
      co_return;
    }
  }
}

asio::awaitable<std::string> ControlSession::run(const control::Run& run) {
  auto writer = std::make_shared<EventWriter>(socket_);
  CommandStop stop;
  // The listener ends before this does: it refers to the socket, the input and `stop`.
  bool listening = true;
  bool run_over = false;  // a listener that had not begun reading yet then reads nothing
  asio::steady_timer listener_done(socket_.get_executor(), asio::steady_timer::time_point::max());
  asio::co_spawn(socket_.get_executor(), listen_for_stop(stop, run_over), [&](std::exception_ptr) {
    listening = false;
    listener_done.cancel();
  });
  const auto emit = [writer, &stop](std::string json) {
    // A command that does not read its events is stopped rather than queued for without end.
    if (!writer->push(formatted(control::Event{std::move(json)})) && !stop.requested)
      stop.request();
  };
  int code = 1;
  try {
    code = co_await setup_.runner(run.request, *bus_, setup_.by, emit, stop);
  } catch (const std::exception& e) {
    // The runner says its own failures as events; this is one it could not, and the listener
    // below must still be awaited before this frame goes.
    spdlog::error("control socket: a command's run failed: {}", e.what());
  }
  // A command that stopped reading near the end of its run must not hold its session (one of
  // kMaxSessions) for ever: past kDrainTime it is closed, and told nothing more.
  const bool drained = co_await writer->drained(std::chrono::steady_clock::now() + kDrainTime);
  run_over = true;
  if (!drained) {
    boost::system::error_code ignored;
    socket_.close(ignored);
  }
  if (listening) {
    boost::system::error_code ignored;
    socket_.cancel(ignored);
    co_await listener_done.async_wait(asio::redirect_error(asio::use_awaitable, ignored));
  }
  co_return formatted(control::Exit{code});
}

asio::awaitable<std::string> ControlSession::answer(const std::string& line, bool& done) {
  auto message = control::parse_command(line);
  if (!versions_agree_) co_return version(message ? &*message : nullptr, done);
  if (!message) {
    done = true;
    co_return formatted(control::Refused{message.error()});
  }
  if (const auto* asked = std::get_if<control::Hello>(&*message)) co_return hello(*asked);
  if (!bus_) {
    done = true;
    co_return formatted(control::Refused{"ask for a bus first (hello PORT)"});
  }
  if (const auto* requested = std::get_if<control::Run>(&*message)) {
    done = true;  // one run a session
    if (!setup_.runner)
      co_return formatted(control::Refused{"this gateway runs no commissioning commands"});
    co_return co_await run(*requested);
  }
  if (std::holds_alternative<control::Stop>(*message)) {
    done = true;
    co_return formatted(control::Exit{0});
  }
  done = true;
  co_return formatted(control::Refused{"say hello PORT, then run REQUEST"});
}

}  // namespace tiltgate
