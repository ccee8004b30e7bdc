// Who may do what over HTTP (docs/web-console.md): the one handler of the HTTP server
// (http/http_server.h). Without [http] users_file it answers as the read-only status API
// always has. With it, the page, /healthz and /metrics stay open to whoever [http] allow admits;
// every /api/ endpoint but /api/login needs a session (a cookie), every change also the
// session's CSRF token in X-CSRF-Token and, when the browser sends one, an Origin that is this
// server; and the session's role must allow the change (viewer < operator < admin).
//
// Threads: runs on the HTTP server's own thread. What the gateway holds (the status copy, the
// angle history, a sensor write) is taken on the buses' executor, awaited here; a password is
// checked on a thread of its own (tens of milliseconds by design), so neither the buses nor the
// other HTTP clients wait for it.
#pragma once

#include <boost/asio/any_io_executor.hpp>
#include <boost/asio/awaitable.hpp>
#include <boost/asio/thread_pool.hpp>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "accounts/users_file.h"
#include "audit/audit_trail.h"
#include "config/config.h"
#include "console/bus_actions.h"
#include "console/config_endpoint.h"
#include "console/config_forms.h"
#include "console/login_throttle.h"
#include "console/session_table.h"
#include "console/settings_endpoint.h"
#include "driver/family.h"
#include "driver/family_commands.h"
#include "http/http_routes.h"
#include "http/monitoring_routes.h"
#include "monitoring/baseline_answer.h"

namespace tiltgate {

class Gateway;

// Whose counters a reset sets back to zero.
enum class CounterScope { sensor, bus };

// What the console reaches of the running gateway.
struct ConsoleContext {
  boost::asio::any_io_executor gateway_executor;  // the buses': status, history and writes
  StatusSource status;
  HistorySource history;
  // Events and the long record (http/monitoring_routes.h), read on the HTTP thread; empty
  // functions: none kept.
  MonitoringSource monitoring;
  const Gateway* gateway = nullptr;
  FamilyList families;
  AuditTrail* audit = nullptr;
  std::string config_path;  // the served file; empty: none (the demo)
  FamilyCommandsList commands;  // the families' raw requests, for a raw frame
  // Sets a sensor's counters, or a bus's and its sensors', back to zero
  // (Gateway::reset_sensor_counters(), reset_bus_counters()); on the buses' executor. False: no
  // such sensor or bus is served. None: resets are refused.
  std::function<bool(CounterScope, std::string_view)> reset_counters;
  // A sensor's baseline shown or changed (monitoring/baseline_runner.h answer_baseline()): the
  // request as `tiltgate baseline` sends it, on the buses' executor. None: refused.
  std::function<monitoring::BaselineAnswer(const std::string& request, const WriteOrigin& by)>
      baseline;
  // Asks the gateway to reload its configuration file (as SIGHUP does), on any thread.
  std::function<void()> reload;
  // Where an applied configuration awaits its confirmation; none: applies are refused.
  ConfirmWindow* confirm_window = nullptr;
};

// Counted for /metrics.
struct ConsoleStats {
  std::uint64_t logins = 0;
  std::uint64_t login_failures = 0;
  std::uint64_t logins_throttled = 0;
  std::uint64_t sessions = 0;  // open now
};

// What the console keeps across a reload that restarts the HTTP server (a changed [http]), so
// that applying a configuration logs nobody out and forgets no failed login: shared by the
// handler of the server being replaced, which may still finish a request, and the new one.
struct ConsoleState {
  ConsoleState(std::chrono::seconds idle, std::chrono::seconds max) : sessions(idle, max) {}
  std::mutex mutex;
  SessionTable sessions;
  LoginThrottle throttle;
  ConsoleStats stats;  // sessions: filled in when read
};
class ConsoleHandler {
 public:
  ConsoleHandler(ConsoleContext context, const HttpConfig& config,
                 std::shared_ptr<ConsoleState> state);
  ~ConsoleHandler();

  boost::asio::awaitable<HttpReply> handle(HttpRequest request);
  // Whether a Cookie header names a live session: what the HTTP server gives logged-in users
  // their share of itself by (HttpServerOptions::signed_in). Any thread.
  bool signed_in(std::string_view cookie_header) const;
  ConsoleStats stats() const;

 private:
  struct Caller;  // the session a request came with, when any

  boost::asio::awaitable<HttpReply> public_route(const HttpRequest& request);
  boost::asio::awaitable<HttpReply> login(const HttpRequest& request);
  HttpReply session_reply(const HttpRequest& request);
  HttpReply logout(const HttpRequest& request);
  boost::asio::awaitable<HttpReply> api(const HttpRequest& request, const ConsoleSession& session);
  boost::asio::awaitable<HttpReply> settings(const HttpRequest& request, std::string_view path,
                                             const ConsoleSession& session);
  static constexpr std::string_view kSensorPrefix = "/api/sensors/";
  // /api/buses/NAME/scan and /api/buses/NAME/raw (console/console_bus_routes.cpp).
  static constexpr std::string_view kBusPrefix = "/api/buses/";
  boost::asio::awaitable<HttpReply> bus_action(const HttpRequest& request, std::string_view path,
                                               const ConsoleSession& session);
  // POST /api/sensors/NAME/counters/reset and /api/buses/NAME/counters/reset
  // (console/console_counter_routes.cpp).
  static constexpr std::string_view kCountersResetSuffix = "/counters/reset";
  boost::asio::awaitable<HttpReply> counters_reset(const HttpRequest& request,
                                                   std::string_view path,
                                                   const ConsoleSession& session);
  // GET and POST /api/sensors/NAME/baseline (console/console_baseline_routes.cpp).
  static constexpr std::string_view kBaselineSuffix = "/baseline";
  boost::asio::awaitable<HttpReply> baseline_route(const HttpRequest& request,
                                                   std::string_view path,
                                                   const ConsoleSession& session);
  // GET /api/buses/NAME/frames and /api/buses/NAME/capture.pcapng
  // (console/console_traffic_routes.cpp).
  static constexpr std::string_view kFramesSuffix = "/frames";
  static constexpr std::string_view kCaptureSuffix = "/capture.pcapng";
  boost::asio::awaitable<HttpReply> traffic_route(const HttpRequest& request,
                                                  std::string_view path,
                                                  const ConsoleSession& session);
  boost::asio::awaitable<HttpReply> config_route(const HttpRequest& request, std::string_view path,
                                                 const ConsoleSession& session);
  HttpReply config_change(const HttpRequest& request, std::string_view path,
                          const ConsoleSession& session, const ServedConfig& served);
  // What the served configuration says that a request needs, read on the buses' thread, where
  // a reload changes it.
  struct ServedFacts {
    std::vector<std::string> buses;
    std::string loaded_at;
  };
  // A copy of the served configuration and Gateway::loads(), for an apply or a confirm.
  struct ServedCopy {
    std::optional<Config> config;
    std::uint64_t loads = 0;
  };
  boost::asio::awaitable<ServedCopy> served_copy();
  boost::asio::awaitable<ServedFacts> served_facts();
  // Refused with the reply when the request may not change anything: no CSRF token of the
  // session, or an Origin that is not this server.
  std::optional<HttpReply> refuse_forgery(const HttpRequest& request,
                                          const ConsoleSession& session) const;
  // The users file, read again when it changed on disk (`tiltgate user` while the gateway runs);
  // the sessions of accounts removed, or whose role or password changed, end then. Called at
  // every /api/ request and login, before anything else is done with it.
  std::shared_ptr<const UsersFile> users();
  // Whether `user`'s account in the users file now is the one in `checked` (same role, same hash).
  bool unchanged_account(const UsersFile& checked, std::string_view user);
  // What stat() says of the users file; all zero when it is missing.
  struct UsersFileStamp {
    std::uint64_t device = 0, inode = 0;
    std::int64_t size = -1, mtime_ns = 0, ctime_ns = 0;
    bool operator==(const UsersFileStamp&) const = default;
  };
  void record(const ConsoleSession& session, std::string sensor, std::string setting,
              std::string old_value, std::string new_value, std::string result);

  ConsoleContext context_;
  HttpConfig config_;
  ConfigEndpoint config_endpoint_;
  ConfigForms config_forms_;
  SettingsEndpoint settings_endpoint_;  // used on the buses' executor only
  std::unique_ptr<BusActions> bus_actions_;  // made on the server's thread, at its first use
  std::shared_ptr<ConsoleState> state_;
  std::shared_ptr<const UsersFile> users_;
  std::string users_error_;
  std::optional<UsersFileStamp> users_stamp_;  // none: not read yet
  boost::asio::thread_pool hashing_{1};
};

}  // namespace tiltgate
