#include "redundancy/redundancy_controller.h"

#include <boost/asio/co_spawn.hpp>
#include <boost/asio/detached.hpp>
#include <boost/asio/post.hpp>
#include <boost/asio/redirect_error.hpp>
#include <boost/asio/use_awaitable.hpp>
#include <spdlog/spdlog.h>

#include <algorithm>

#include "line_scheduling/bus_scheduler.h"
#include "serial/serial_line.h"

namespace tiltgate {

namespace asio = boost::asio;

namespace {

double unix_now() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch())
      .count();
}

std::int64_t ms_of(std::chrono::steady_clock::duration d) {
  return std::chrono::duration_cast<std::chrono::milliseconds>(d).count();
}

asio::awaitable<void> pause_for(asio::any_io_executor executor, std::chrono::milliseconds time) {
  asio::steady_timer timer(executor, time);
  boost::system::error_code ignored;
  co_await timer.async_wait(asio::redirect_error(asio::use_awaitable, ignored));
}

}  // namespace

RedundancyController::RedundancyController(asio::any_io_executor executor,
                                           RedundancyConfig config, PeerProbe probe)
    : executor_(executor), config_(std::move(config)), probe_(std::move(probe)), tick_(executor) {}

RedundancyController::~RedundancyController() { stop(); }

void RedundancyController::add_bus(RedundantBus config) {
  auto bus = std::make_shared<Bus>();
  bus->heard = std::make_shared<HeardExchanges>(executor_, *config.line, config.character_time);
  const PassiveFramer framer = config.listening ? config.listening->framer : nullptr;
  bus->guard = std::make_unique<MasterGuard>(
      config.name, framer, config.character_time, [this](std::string why) {
        // Not under the line's own transaction: its line is stopped from there.
        asio::post(executor_, [this, why = std::move(why)] { stand_down(why); });
      });
  bus->guard->set_stall_limit(config_.takeover / 2);
  config.line->check_before_sending(
      [guard = bus->guard.get()](std::span<const std::uint8_t> received) {
        return guard->may_send(received);
      });
  bus->config = std::move(config);
  buses_.push_back(bus);
  if (!started_) {
    // The gateway adds its first buses one after another: it starts once they all are.
    if (!start_posted_) asio::post(executor_, [this] { start(); });
    start_posted_ = true;
    return;
  }
  if (active_)
    transmit(*bus);
  else
    listen(*bus);
}

void RedundancyController::remove_bus(const BusScheduler* scheduler) {
  std::erase_if(buses_, [&](const std::shared_ptr<Bus>& bus) {
    if (bus->config.scheduler != scheduler) return false;
    if (bus->listener) bus->listener->stop();
    bus->heard->stop_waits();
    bus->config.line->check_before_sending(nullptr);
    return true;
  });
}

void RedundancyController::start() {
  if (started_ || stopped_) return;
  started_ = true;
  listening_since_ = Clock::now();
  since_unix_ = unix_now();
  reason_ = "listening first: another master may be active on the lines";
  spdlog::info("redundancy: {} of a pair with {}:{}, listening to the lines before it sends "
               "(takeover after {} ms without a request heard)",
               config_.role == RedundancyConfig::Role::primary ? "primary" : "standby",
               config_.peer_host, config_.peer_port, silence_needed().count());
  for (const auto& bus : buses_) listen(*bus);
  asio::co_spawn(executor_, watch(), asio::detached);
}

void RedundancyController::stop() {
  if (stopped_) return;
  stopped_ = true;
  tick_.cancel();
  for (const auto& bus : buses_) {
    if (bus->listener) bus->listener->stop();
    bus->heard->stop_waits();
    bus->guard->hold();
  }
}

std::chrono::milliseconds RedundancyController::silence_needed() const {
  // A standby asks the peer after takeover_ms less the question's time-out, so that its first
  // request goes out within takeover_ms of the master's last. A primary goes after half of it:
  // starting beside a standby (the plant powered up), it takes the lines first, and the
  // standby, asking, finds it active. Either hears an active master's requests more often than
  // that (tiltgate check: takeover_ms is at least twice every line's shortest poll).
  return config_.role == RedundancyConfig::Role::standby ? config_.takeover - probe_.timeout
                                                         : config_.takeover / 2;
}

RedundancyController::Clock::time_point RedundancyController::last_heard() const {
  Clock::time_point last = listening_since_;
  for (const auto& bus : buses_)
    if (const auto heard = bus->heard->last_request()) last = std::max(last, *heard);
  return last;
}

void RedundancyController::listen(Bus& bus) {
  bus.guard->hold();
  if (bus.line_started) bus.config.line->stop();
  bus.heard->resume_waits();
  bus.config.scheduler->listen_to(bus.heard.get());
  bus.closed_since.reset();
  if (!bus.config.listening) return;  // a device server's: nothing to listen to
  for (const auto& shared : buses_)
    if (shared.get() == &bus) asio::co_spawn(executor_, keep_listening(shared), asio::detached);
}

asio::awaitable<void> RedundancyController::keep_listening(std::shared_ptr<Bus> bus) {
  // One listener at a time per bus: one still closing makes the next wait for its lock.
  while (!stopped_ && !active_ && bus->listener == nullptr) {
    auto listener = std::make_unique<LineListener>(executor_, *bus->config.listening, *bus->heard);
    const auto opened = listener->open();
    if (!opened) {
      const auto now = Clock::now();
      if (!bus->listen_failed_logged || now - *bus->listen_failed_logged > std::chrono::minutes(1)) {
        spdlog::error("{}: cannot listen to {}: {}; trying every second", bus->config.name,
                      bus->config.listening->path, opened.error());
        bus->listen_failed_logged = now;
      }
      co_await pause_for(executor_, std::chrono::seconds{1});
      continue;
    }
    bus->listen_failed_logged.reset();
    spdlog::info("{}: listening to {} (receive only)", bus->config.name,
                 bus->config.listening->path);
    bus->listener = std::move(listener);
    const auto ended = co_await bus->listener->run();
    bus->listener.reset();
    if (!ended) break;  // stopped: the gateway takes the line, or stops
    spdlog::warn("{}: listening to {} ended ({}); again in a second", bus->config.name,
                 bus->config.listening->path, *ended);
    co_await pause_for(executor_, std::chrono::seconds{1});
  }
}

void RedundancyController::transmit(Bus& bus) {
  if (bus.listener) bus.listener->stop();
  // The pollers leave the heard line first, then their waits on it end.
  bus.config.scheduler->listen_to(nullptr);
  bus.heard->stop_waits();
  bus.guard->arm(Clock::now());
  if (!bus.line_started) {
    bus.line_started = true;
    bus.config.line->start();
  } else if (!bus.config.line->restart()) {
    spdlog::error("{}: its port cannot be opened again after this gateway stood down (a device "
                  "server's): restart the gateway to serve it",
                  bus.config.name);
  }
}

void RedundancyController::take_over(std::string why) {
  if (active_ || stopped_) return;
  active_ = true;
  ++takeovers_;
  reason_ = std::move(why);
  since_unix_ = unix_now();
  spdlog::warn("redundancy: taking the lines: {}", reason_);
  for (const auto& bus : buses_) transmit(*bus);
  if (role_changed_) role_changed_(true);
  // The feeds started in that call, on this thread (a store read from disk): time this gateway
  // spent on them is no stall of its own.
  const auto now = Clock::now();
  last_tick_ = now;
  for (const auto& bus : buses_) bus->guard->alive(now);
}

void RedundancyController::stand_down(std::string why) {
  if (!active_ || stopped_) return;
  active_ = false;
  ++step_downs_;
  reason_ = std::move(why);
  since_unix_ = unix_now();
  listening_since_ = Clock::now();
  spdlog::error("redundancy: standing down, sending nothing more, listening: {}", reason_);
  for (const auto& bus : buses_) listen(*bus);
  if (role_changed_) role_changed_(false);
}

asio::awaitable<void> RedundancyController::watch() {
  while (!stopped_) {
    tick_.expires_after(kTick);
    boost::system::error_code ec;
    co_await tick_.async_wait(asio::redirect_error(asio::use_awaitable, ec));
    if (stopped_) break;
    const auto now = Clock::now();
    const auto stall = last_tick_ ? now - *last_tick_ : Clock::duration{0};
    last_tick_ = now;
    if (active_ && stall > config_.takeover / 2) {
      stand_down(fmt::format("this gateway was held up for {} ms (stopped, or starved of CPU): "
                             "the standby may have taken the lines meanwhile",
                             ms_of(stall)));
      continue;
    }
    for (const auto& bus : buses_) bus->guard->alive(now);
    // The peer is asked beside the ticks, which must go on meanwhile: a tick late by the
    // probe's time-out would read as a stall.
    if (probing_) continue;
    if (active_ ? due_closed_line(now).has_value() || failback_due(now)
                : now - last_heard() >= silence_needed()) {
      probing_ = true;
      asio::co_spawn(executor_, ask_and_decide(), asio::detached);
    }
  }
}

std::optional<std::string> RedundancyController::due_closed_line(Clock::time_point now) {
  // A line that stays closed (an unplugged adapter) serves nobody from here: the peer,
  // answering, may have it.
  std::optional<std::string> closed;
  for (const auto& bus : buses_) {
    if (bus->config.line->is_open()) {
      bus->closed_since.reset();
      continue;
    }
    if (!bus->closed_since) bus->closed_since = now;
    if (now - *bus->closed_since > config_.takeover / 2)
      closed = fmt::format("{}: its port has been closed for {} ms and the peer answers",
                           bus->config.name, ms_of(now - *bus->closed_since));
  }
  return closed;
}

bool RedundancyController::failback_due(Clock::time_point now) const {
  return config_.failback && config_.role == RedundancyConfig::Role::standby &&
         (!last_failback_probe_ || now - *last_failback_probe_ > config_.takeover);
}

asio::awaitable<void> RedundancyController::ask_and_decide() {
  const auto asked = Clock::now();
  const bool failback = active_ && failback_due(asked);
  if (failback) last_failback_probe_ = asked;
  const PeerAnswer answer = co_await ask_peer(executor_, probe_);
  probing_ = false;
  if (stopped_) co_return;
  const auto now = Clock::now();
  if (active_) {
    if (const auto closed = due_closed_line(now); closed && answer != PeerAnswer::none)
      stand_down(*closed);
    else if (failback && answer == PeerAnswer::standby)
      stand_down("failback: the primary is back and listening");
    co_return;
  }
  const auto silent = now - last_heard();
  if (silent < silence_needed()) {  // the master spoke while we asked
    peer_active_logged_ = false;
    co_return;
  }
  if (answer == PeerAnswer::active) {
    if (!peer_active_logged_)
      spdlog::warn("redundancy: no request heard on any line for {} ms, but the peer {}:{} "
                   "answers as the active gateway: not taking the lines",
                   ms_of(silent), config_.peer_host, config_.peer_port);
    peer_active_logged_ = true;
    co_return;
  }
  take_over(fmt::format("no request heard on any line for {} ms, and the peer {}:{} {}",
                        ms_of(silent), config_.peer_host, config_.peer_port, to_string(answer)));
}

RedundancyStatus RedundancyController::status() const {
  RedundancyStatus status;
  status.configured_role = config_.role == RedundancyConfig::Role::primary ? "primary" : "standby";
  status.active = active_;
  status.takeovers = takeovers_;
  status.step_downs = step_downs_;
  status.since_seconds = since_unix_;
  status.reason = reason_;
  // As [redundancy] peer is written: an IPv6 address in brackets.
  const bool ipv6 = config_.peer_host.find(':') != std::string::npos;
  status.peer = ipv6 ? fmt::format("[{}]:{}", config_.peer_host, config_.peer_port)
                     : fmt::format("{}:{}", config_.peer_host, config_.peer_port);
  status.takeover_ms = config_.takeover.count();
  status.failback = config_.failback;
  std::optional<Clock::time_point> last;
  for (const auto& bus : buses_)
    if (const auto heard = bus->heard->last_request()) last = std::max(last.value_or(*heard), *heard);
  if (last) status.last_request_heard_ms = ms_of(Clock::now() - *last);
  return status;
}

}  // namespace tiltgate
