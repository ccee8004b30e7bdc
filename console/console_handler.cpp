#include "console/console_handler.h"

#include <sys/stat.h>

#include <variant>

#include <boost/asio/co_spawn.hpp>
#include <boost/asio/use_awaitable.hpp>
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "console/audit_endpoint.h"
#include "console/console_audit.h"
#include "console/console_reply.h"
#include "console/console_requests.h"
#include "console/request_guard.h"
#include "driver/visible_text.h"
#include "gateway/gateway.h"
#include "http/monitoring_routes.h"

namespace tiltgate {

namespace asio = boost::asio;
using json = nlohmann::json;
using Clock = std::chrono::steady_clock;

namespace {

constexpr std::string_view kSettingsSuffix = "/settings";

std::string_view path_of(std::string_view target) { return target.substr(0, target.find('?')); }

bool changes(std::string_view method) {
  return method == "POST" || method == "PUT" || method == "DELETE" || method == "PATCH";
}

}  // namespace

ConsoleHandler::ConsoleHandler(ConsoleContext context, const HttpConfig& config,
                               std::shared_ptr<ConsoleState> state)
    : context_(std::move(context)),
      config_(config),
      config_endpoint_(context_.config_path, context_.families, context_.confirm_window),
      config_forms_(context_.config_path, context_.families),
      settings_endpoint_(context_.gateway, context_.families, context_.audit),
      state_(std::move(state)) {
  {
    std::lock_guard lock(state_->mutex);
    state_->sessions.set_limits(config.session_idle, config.session_max);
  }
  if (!config_.users_file.empty()) users();
}

ConsoleHandler::~ConsoleHandler() {
  hashing_.stop();
  hashing_.join();
}

bool ConsoleHandler::signed_in(std::string_view cookie_header) const {
  const std::string token = session_token(cookie_header);
  if (token.empty()) return false;
  std::lock_guard lock(state_->mutex);
  return state_->sessions.live(token, Clock::now());
}

ConsoleStats ConsoleHandler::stats() const {
  std::lock_guard lock(state_->mutex);
  ConsoleStats stats = state_->stats;
  stats.sessions = state_->sessions.size();
  return stats;
}

std::shared_ptr<const UsersFile> ConsoleHandler::users() {
  // One stat() a request (about a microsecond): the file as it is now, checked on this thread
  // just before the request's session is looked up, so no request is served on a session its
  // account no longer allows. `tiltgate user` replaces the file by a rename (a new inode); an
  // editor may write it in place (a new size, mtime or ctime).
  struct stat info {};
  UsersFileStamp stamp;
  if (::stat(config_.users_file.c_str(), &info) == 0)
    stamp = {std::uint64_t(info.st_dev), std::uint64_t(info.st_ino), std::int64_t(info.st_size),
             std::int64_t(info.st_mtim.tv_sec) * 1'000'000'000 + info.st_mtim.tv_nsec,
             std::int64_t(info.st_ctim.tv_sec) * 1'000'000'000 + info.st_ctim.tv_nsec};
  if (users_stamp_ && *users_stamp_ == stamp) return users_;
  users_stamp_ = stamp;
  auto loaded = UsersFile::load(config_.users_file);
  if (!loaded) {
    if (users_error_ != loaded.error())
      spdlog::error("web console: no logins: {}", visible_text(loaded.error()));
    users_error_ = loaded.error();
    users_.reset();
  } else {
    users_error_.clear();
    users_ = std::make_shared<const UsersFile>(std::move(*loaded));
    // Said once per change of the file (this runs only then), never per request.
    for (const std::string& skipped : users_->skipped())
      spdlog::error("web console: line skipped: {}", visible_text(skipped));
    spdlog::info("web console: {} account(s) from {}{}", users_->accounts().size(),
                 visible_text(config_.users_file),
                 users_->skipped().empty()
                     ? std::string()
                     : fmt::format(", {} malformed line(s) skipped", users_->skipped().size()));
  }
  std::size_t ended = 0;
  {
    std::lock_guard lock(state_->mutex);
    ended = state_->sessions.end_changed(users_.get());
  }
  if (ended > 0)
    spdlog::info("web console: {} session(s) ended: their account was removed, or its role or "
                 "password changed, or its line is malformed",
                 ended);
  return users_;
}

bool ConsoleHandler::unchanged_account(const UsersFile& checked, std::string_view user) {
  const std::shared_ptr<const UsersFile> now = users();
  const UserAccount* then_account = checked.find(user);
  const UserAccount* now_account = now ? now->find(user) : nullptr;
  return then_account != nullptr && now_account != nullptr &&
         then_account->role == now_account->role && then_account->hash == now_account->hash;
}

void ConsoleHandler::record(const ConsoleSession& session, std::string sensor,
                            std::string setting, std::string old_value, std::string new_value,
                            std::string result) {
  record_console_change(context_.audit, session.user, std::move(sensor), std::move(setting),
                        std::move(old_value), std::move(new_value), std::move(result));
}

asio::awaitable<HttpReply> ConsoleHandler::public_route(const HttpRequest& request) {
  // The monitoring's (http/monitoring_routes.h) here, on the HTTP thread: a long record's
  // download reads files, which the buses' executor must never wait for.
  const std::int64_t now_unix_ms = std::chrono::duration_cast<std::chrono::milliseconds>(
      std::chrono::system_clock::now().time_since_epoch()).count();
  if (auto reply = route_monitoring(request.method, request.target, context_.monitoring,
                                    now_unix_ms))
    co_return *reply;
  // Taken on the buses' executor, where the status and the history live: as quick as it ever
  // was there, and the HTTP thread only waits for it.
  // Named, not a temporary in the co_await: g++ 12 destroys such a temporary twice.
  auto route = [&]() -> asio::awaitable<HttpReply> {
    co_return route_http(request.method, request.target, context_.status, context_.history);
  };
  co_return co_await asio::co_spawn(context_.gateway_executor, std::move(route),
                                    asio::use_awaitable);
}

asio::awaitable<ConsoleHandler::ServedFacts> ConsoleHandler::served_facts() {
  // Named, not a temporary in the co_await: g++ 12 destroys such a temporary twice.
  auto take = [this]() -> asio::awaitable<ServedFacts> {
    ServedFacts facts;
    if (context_.gateway != nullptr) {
      for (const BusConfig& bus : context_.gateway->config().buses) facts.buses.push_back(bus.name);
      facts.loaded_at = context_.gateway->loaded_at();
    }
    co_return facts;
  };
  co_return co_await asio::co_spawn(context_.gateway_executor, std::move(take),
                                    asio::use_awaitable);
}

asio::awaitable<HttpReply> ConsoleHandler::handle(HttpRequest request) {
  const std::string_view path = path_of(request.target);
  if (config_.users_file.empty()) {
    if (path == "/api/session" && request.method == "GET")
      co_return json_reply(200, json{{"accounts", false}});
    co_return co_await public_route(request);
  }
  if (!path.starts_with("/api/")) co_return co_await public_route(request);
  if (path == "/api/login") {
    if (request.method != "POST") co_return error_reply(405, "log in with POST");
    co_return co_await login(request);
  }
  // The users file as it is now, before any session is looked up (docs/web-console.md, "When a
  // session ends").
  users();
  if (path == "/api/session" && request.method == "GET") co_return session_reply(request);
  // A copy: the table may drop the session while this request waits (a logout, an expiry).
  ConsoleSession session;
  {
    std::lock_guard lock(state_->mutex);
    const ConsoleSession* found = state_->sessions.use(session_token(request.cookie), Clock::now());
    if (found != nullptr) session = *found;
  }
  if (session.user.empty()) co_return error_reply(401, "log in first");
  if (changes(request.method)) {
    if (auto refused = refuse_forgery(request, session)) co_return *refused;
  }
  co_return co_await api(request, session);
}

std::optional<HttpReply> ConsoleHandler::refuse_forgery(const HttpRequest& request,
                                                        const ConsoleSession& session) const {
  if (!same_secret(request.csrf_token, session.csrf))
    return error_reply(403, "the request lacks this session's X-CSRF-Token");
  if (!same_origin(request.origin, request.host, request.https))
    return error_reply(403, fmt::format("a request from {} may not change anything here",
                                        request.origin));
  return std::nullopt;
}

HttpReply ConsoleHandler::session_reply(const HttpRequest& request) {
  std::lock_guard lock(state_->mutex);
  const ConsoleSession* session =
      state_->sessions.use(session_token(request.cookie), Clock::now());
  if (session == nullptr) return json_reply(401, json{{"accounts", true}, {"error", "log in"}});
  return json_reply(200, json{{"accounts", true},
                              {"user", session->user},
                              {"role", role_name(session->role)},
                              {"csrf", session->csrf}});
}

asio::awaitable<HttpReply> ConsoleHandler::login(const HttpRequest& request) {
  if (!login_allowed(request.https, request.loopback))
    co_return error_reply(403, "log in over HTTPS ([http] tls_cert_file), or from this machine: "
                               "a password never crosses the network in clear");
  if (!same_origin(request.origin, request.host, request.https))
    co_return error_reply(403, fmt::format("a login from {} is not accepted here", request.origin));
  auto asked = parse_login_request(request.body);
  if (!asked) co_return error_reply(400, asked.error());
  const std::shared_ptr<const UsersFile> accounts = users();
  if (!accounts) co_return error_reply(503, "no accounts can be read: see the gateway's log");
  // Counted before the hash, so attempts sent together cannot all pass
  // (docs/web-console.md, "Logins and guessing").
  std::variant<LoginThrottle::Admitted, LoginThrottle::Refused> admission;
  {
    std::lock_guard lock(state_->mutex);
    admission = state_->throttle.admit(asked->user, accounts->find(asked->user) != nullptr,
                                       request.address, Clock::now());
    if (std::holds_alternative<LoginThrottle::Refused>(admission)) {
      ++state_->stats.logins_throttled;
    }
  }
  if (const auto* refused = std::get_if<LoginThrottle::Refused>(&admission)) {
    const auto wait = refused->wait.count();
    const std::string why =
        refused->limit == LoginThrottle::Limit::address
            ? fmt::format("too many failed logins from this address: try again in {} s", wait)
            : fmt::format("too many login attempts for this account: try again in {} s", wait);
    HttpReply reply = json_reply(429, json{{"error", why}, {"retry_after_s", wait}});
    reply.headers.emplace_back("Retry-After", std::to_string(wait));
    co_return reply;
  }
  const LoginThrottle::Admitted attempt = std::get<LoginThrottle::Admitted>(admission);
  // The hash on its own thread: it costs tens of milliseconds by design.
  const std::string user = asked->user;
  const std::string password = std::move(asked->password);
  // Named, not a temporary in the co_await: g++ 12 destroys such a temporary twice.
  auto check = [accounts, user, password]() -> asio::awaitable<std::optional<Role>> {
    co_return accounts->verify(user, password);
  };
  std::optional<Role> role =
      co_await asio::co_spawn(hashing_.get_executor(), std::move(check), asio::use_awaitable);
  // The file may have changed while the hash was checked (a `tiltgate user passwd` meanwhile):
  // a session opens only for the account as it is now, so the old password opens none.
  if (role && !unchanged_account(*accounts, user)) role.reset();
  if (!role) {
    {
      std::lock_guard lock(state_->mutex);
      ++state_->stats.login_failures;  // the throttle counted it already
    }
    spdlog::warn("web console: failed login as \"{}\" from {}", visible_text(user),
                 request.address);
    co_return error_reply(401, "wrong user name or password");
  }
  std::string token, csrf;
  {
    std::lock_guard lock(state_->mutex);
    state_->throttle.succeeded(attempt);
    token = state_->sessions.open(user, *role, accounts->find(user)->hash, Clock::now());
    csrf = state_->sessions.use(token, Clock::now())->csrf;
    ++state_->stats.logins;
  }
  spdlog::info("web console: {} logged in from {} as {}", visible_text(user), request.address,
               role_name(*role));
  HttpReply reply = json_reply(
      200, json{{"user", user}, {"role", role_name(*role)}, {"csrf", csrf}});
  reply.headers.emplace_back("Set-Cookie", session_cookie(token, request.https, request.loopback));
  co_return reply;
}

HttpReply ConsoleHandler::logout(const HttpRequest& request) {
  {
    std::lock_guard lock(state_->mutex);
    state_->sessions.close(session_token(request.cookie));
  }
  HttpReply reply = json_reply(200, json::object());
  reply.headers.emplace_back(
      "Set-Cookie", fmt::format("{}=; HttpOnly; SameSite=Strict; Path=/; Max-Age=0", kSessionCookie));
  return reply;
}

asio::awaitable<HttpReply> ConsoleHandler::api(const HttpRequest& request,
                                               const ConsoleSession& session) {
  const std::string_view path = path_of(request.target);
  const std::string& method = request.method;
  if (path == "/api/logout") {
    if (method != "POST") co_return error_reply(405, "log out with POST");
    co_return logout(request);
  }
  if (path == "/api/audit") {
    if (method != "GET") co_return error_reply(405, "GET only");
    co_return audit_reply(context_.audit, request.target);
  }
  if (path == "/api/config" || path.starts_with("/api/config/") || path == "/api/config.toml")
    co_return co_await config_route(request, path, session);
  if (path.ends_with(kCountersResetSuffix) &&
      (path.starts_with(kSensorPrefix) || path.starts_with(kBusPrefix)))
    co_return co_await counters_reset(request, path, session);
  if (path.starts_with(kSensorPrefix) && path.ends_with(kBaselineSuffix))
    co_return co_await baseline_route(request, path, session);
  if (path.starts_with(kSensorPrefix) && path.ends_with(kSettingsSuffix))
    co_return co_await settings(request, path, session);
  if (path.starts_with(kBusPrefix) && (path.ends_with("/scan") || path.ends_with("/raw")))
    co_return co_await bus_action(request, path, session);
  if (path.starts_with(kBusPrefix) &&
      (path.ends_with(kFramesSuffix) || path.ends_with(kCaptureSuffix)))
    co_return co_await traffic_route(request, path, session);
  if (method == "GET" || method == "HEAD") co_return co_await public_route(request);
  co_return error_reply(405, "not something that can be changed");
}

asio::awaitable<HttpReply> ConsoleHandler::settings(const HttpRequest& request,
                                                    std::string_view path,
                                                    const ConsoleSession& session) {
  const auto name = path_name(
      path.substr(kSensorPrefix.size(), path.size() - kSensorPrefix.size() - kSettingsSuffix.size()));
  if (!name) co_return error_reply(404, "no such sensor");
  const bool write = request.method == "POST";
  if (!write && request.method != "GET")
    co_return error_reply(405, "GET a sensor's settings, or POST one to change it");
  std::optional<SettingRequest> asked;
  if (write) {
    auto parsed = parse_setting_request(request.body);
    if (!parsed) co_return error_reply(400, parsed.error());
    asked = std::move(*parsed);
  }
  // Looked up on the buses' executor, where the sensors and their maps live; the write is
  // queued there too, and this request waits for the sensor's answer without holding it.
  // Named, not a temporary in the co_await: g++ 12 destroys such a temporary twice.
  auto on_bus = [&]() -> asio::awaitable<HttpReply> {
    if (!asked) co_return settings_endpoint_.list(*name);
    co_return co_await settings_endpoint_.change(*name, *asked, session.user, session.role);
  };
  co_return co_await asio::co_spawn(context_.gateway_executor, std::move(on_bus),
                                    asio::use_awaitable);
}

}  // namespace tiltgate
