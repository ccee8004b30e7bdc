// The HTTP status API, its metrics, the status page and the web console ([http]), with the
// angle history the page's graphs draw: a service attached to the gateway
// (gateway/gateway_service.h). The server runs on a thread of its own (http/http_thread.h);
// the
// history is recorded every [http] history_interval_ms from the same status copy the API
// serves; a reload that changes [http] restarts the server, one that changes the sensors keeps
// the graphs of the sensors that keep their name.
#pragma once

#include <boost/asio/any_io_executor.hpp>
#include <boost/asio/awaitable.hpp>
#include <boost/asio/steady_timer.hpp>
#include <memory>
#include <vector>

#include "config/config.h"
#include "gateway/gateway.h"
#include "gateway/gateway_service.h"
#include "gateway/retired.h"
#include "console/console_handler.h"
#include "status/history_recorder.h"
#include "http/http_thread.h"

namespace tiltgate {

class HttpService final : public GatewayService {
 public:
  // `status`: the gateway's whole status, as the API shows it (the core's and the services').
  // `console`: what the web console reaches besides (the audit trail, the families, reload);
  // its executor, status and history are filled in here.
  HttpService(const Gateway& gateway, StatusSource status, ConsoleContext console = {});
  ~HttpService() override;

  void start() override;
  bool reload(const Config& loaded, const ConfigDiff& diff) override;
  void stop() override;
  std::string_view name() const override { return "http"; }

  // Clients refused for [http] allow; 0 while the server is off.
  std::uint64_t connections_denied() const { return http_ ? http_->stats().denied : 0; }
  // Clients closed for cause (limits, time-outs, bad requests); none while the server is off.
  HttpClientsClosed clients_closed() const {
    return http_ ? http_->stats().closed : HttpClientsClosed{};
  }
  // The request rates in force and what waited under them; zeros while the server is off.
  HttpRequestRates request_rates() const;
  // The bound port; 0 when [http] is off or its port could not be bound (or not yet: a
  // reload's server waits for the one it replaced to let the port go).
  std::uint16_t port() const { return http_ ? http_->local_port() : 0; }
  // The web console's logins and sessions; zeros while the server is off.
  ConsoleCounts console_counts() const;

 private:
  void make_http(const HistoryRecorder* previous);
  // `replaced`: the port of the server a reload replaced, while that one still holds it.
  void start_http(HttpThread::PortRelease replaced = {});
  // The rings for the sensors served now; those of `previous` (by name) carry over.
  void make_history(const HistoryRecorder* previous);
  // Every history_interval_ms: each sensor's angles into its ring.
  boost::asio::awaitable<void> record_history();

  const Gateway& gateway_;
  StatusSource status_;
  ConsoleContext console_;
  HttpConfig config_;
  std::shared_ptr<ConsoleHandler> handler_;   // the server's; none with [http] enabled = false
  // The console's sessions, login throttling and counts, kept across reloads.
  std::shared_ptr<ConsoleState> console_state_;
  std::unique_ptr<HttpThread> http_;          // none with [http] enabled = false
  std::unique_ptr<HistoryRecorder> history_;  // none without http_
  boost::asio::steady_timer history_timer_;
  bool stopping_ = false;
  // Servers a reload replaced, freed once their connections' coroutines have ended.
  Retired<HttpThread> retired_;
};

}  // namespace tiltgate
