#include "console/http_service.h"

#include <boost/asio/co_spawn.hpp>
#include <boost/asio/detached.hpp>
#include <boost/asio/redirect_error.hpp>
#include <boost/asio/use_awaitable.hpp>
#include <spdlog/spdlog.h>

#include <filesystem>

#include "config/broker_keys.h"
#include "driver/visible_text.h"
#include "http/host_check.h"
#include "mapping/model_capabilities.h"

namespace tiltgate {

HttpService::HttpService(const Gateway& gateway, StatusSource status,
                             ConsoleContext console)
    : gateway_(gateway),
      status_(std::move(status)),
      console_(std::move(console)),
      config_(gateway.config().http),
      history_timer_(gateway.executor()),
      retired_(gateway.executor()) {
  make_http(nullptr);
}

HttpService::~HttpService() {
  // The server's own references to the console go with the server, before its loop (HttpThread):
  // this one would keep the console, and its password-hashing pool, alive past that loop, and a
  // login hashed on the pool as the gateway stopped resumed on a freed loop (TSan, a demo stopped
  // right after a refused login).
  handler_.reset();
}

HttpRequestRates HttpService::request_rates() const {
  if (!http_) return {};
  const HttpServerStats stats = http_->stats();
  return {config_.max_requests_per_s, config_.max_client_requests_per_s, stats.requests_delayed,
          stats.delay_seconds};
}

void HttpService::make_http(const HistoryRecorder* previous) {
  if (!config_.enabled) return;
  HttpServerOptions http;
  http.listen = config_.listen;
  http.port = config_.port;
  http.allow = config_.allow;
  http.max_clients_per_host = config_.max_clients_per_host;
  http.max_requests_per_s = config_.max_requests_per_s;
  http.max_client_requests_per_s = config_.max_client_requests_per_s;
  // A configuration's text is the largest body the console takes.
  if (!config_.users_file.empty()) http.max_body_bytes = 512 * 1024;
  http.tls_cert_pem = config_.tls_cert_pem;
  http.tls_key_pem = config_.tls_key_pem;
  http.server_names = config_.server_names.empty()
                          ? default_server_names(config_.listen, config::host_name())
                          : config_.server_names;
  make_history(previous);
  ConsoleContext console = console_;
  console.gateway_executor = gateway_.executor();
  console.status = status_;
  // Called on the buses' executor only (ConsoleHandler::public_route).
  console.history = [this](std::string_view sensor) -> std::optional<std::vector<AngleSample>> {
    if (!history_) return std::nullopt;  // a reload turned [http] off meanwhile
    return history_->history(sensor);
  };
  console.gateway = &gateway_;
  // A configuration made in memory (a test's gateway) has no file to show or replace.
  if (console.config_path.empty() && std::filesystem::is_regular_file(gateway_.config().path))
    console.config_path = gateway_.config().path;
  if (!console_state_)
    console_state_ = std::make_shared<ConsoleState>(config_.session_idle, config_.session_max);
  handler_ = std::make_shared<ConsoleHandler>(std::move(console), config_, console_state_);
  // With accounts, logged-in users keep half of the server however many others come.
  if (!config_.users_file.empty())
    http.signed_in = [handler = handler_](std::string_view cookie) {
      return handler->signed_in(cookie);
    };
  http_ = std::make_unique<HttpThread>(
      [handler = handler_](HttpRequest request) { return handler->handle(std::move(request)); },
      http);
}

ConsoleCounts HttpService::console_counts() const {
  if (!handler_) return {};
  const ConsoleStats stats = handler_->stats();
  return ConsoleCounts{stats.logins, stats.login_failures, stats.logins_throttled, stats.sessions};
}

void HttpService::make_history(const HistoryRecorder* previous) {
  std::vector<std::string> names, with_temperature;
  for (const auto& sensor : gateway_.sensors()) {
    names.push_back(sensor->config.name);
    if (reports_temperature(sensor->model, sensor->config.family_options.device_values()))
      with_temperature.push_back(sensor->config.name);
  }
  history_ = std::make_unique<HistoryRecorder>(
      std::move(names),
      std::size_t(std::chrono::milliseconds(config_.history_seconds) / config_.history_interval),
      with_temperature);
  if (previous != nullptr) history_->carry_over(*previous);
}

void HttpService::start() {
  start_http();
  boost::asio::co_spawn(gateway_.executor(), record_history(), boost::asio::detached);
}

void HttpService::start_http(HttpThread::PortRelease replaced) {
  if (!http_) return;
  // Said at once, or from the HTTP thread once a replaced server has let the port go.
  http_->start(
      [https = config_.https(), listen = config_.listen, users_file = config_.users_file](
          const Expected<Done, std::string>& started, std::uint16_t port) {
        if (!started)
          spdlog::warn("HTTP status API off: {}", visible_text(started.error()));
        else
          spdlog::info("HTTP status API and metrics on {}://{}:{}/{}", https ? "https" : "http",
                       listen, port,
                       users_file.empty()
                           ? ""
                           : " (web console: accounts in " + visible_text(users_file) + ")");
      },
      std::move(replaced));
}

bool HttpService::reload(const Config& loaded, const ConfigDiff& diff) {
  config_ = loaded.http;
  if (diff.http_changed) {
    HttpThread::PortRelease replaced;
    if (http_) {
      http_->stop();  // returns at once; the new server binds once the port is free
      replaced = http_->port_released();
      retired_.add(std::move(http_));
      handler_.reset();
    }
    std::unique_ptr<HistoryRecorder> previous = std::move(history_);
    make_http(previous.get());
    start_http(std::move(replaced));
    return true;
  }
  if (history_ && !diff.sensors_unchanged()) {
    std::unique_ptr<HistoryRecorder> previous = std::move(history_);
    make_history(previous.get());
  }
  return false;
}

void HttpService::stop() {
  stopping_ = true;
  history_timer_.cancel();
  if (http_) http_->stop();
}

boost::asio::awaitable<void> HttpService::record_history() {
  // Runs whether or not [http] is on: a reload may turn it on, or change the interval (which
  // applies from the next sample on).
  auto next = SteadyClock::now() + config_.history_interval;
  while (!stopping_) {
    const auto interval = config_.history_interval;
    history_timer_.expires_at(next);
    boost::system::error_code ec;
    co_await history_timer_.async_wait(
        boost::asio::redirect_error(boost::asio::use_awaitable, ec));
    if (ec || stopping_) co_return;
    const auto unix_ms = std::chrono::duration_cast<std::chrono::milliseconds>(
                             std::chrono::system_clock::now().time_since_epoch())
                             .count();
    if (history_) history_->record(status_(), unix_ms);
    // A steady cadence; after a stall (a suspended machine) start over rather than catch up.
    const auto now = SteadyClock::now();
    next += interval;
    if (next < now) next = now + interval;
  }
}

}  // namespace tiltgate
