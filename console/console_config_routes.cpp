// The web console's configuration routes: GET, check, PUT (an apply under a confirmation window,
// docs/web-console.md, "Applying with a confirmation window"), confirm, the file's download and
// the guided forms' keys, tables and edits. The endpoints (console/config_endpoint.h,
// console/config_forms.h) do the work; this part of the handler reads what
// the gateway serves on the buses' thread and records the apply, and every refused attempt at
// a change.
#include <boost/asio/co_spawn.hpp>
#include <boost/asio/use_awaitable.hpp>
#include <fmt/format.h>

#include "console/apply_audit.h"
#include "console/console_handler.h"
#include "console/console_reply.h"
#include "console/console_requests.h"
#include "console/request_guard.h"
#include "gateway/gateway.h"

namespace tiltgate {

namespace asio = boost::asio;

asio::awaitable<ConsoleHandler::ServedCopy> ConsoleHandler::served_copy() {
  // Named, not a temporary in the co_await: g++ 12 destroys such a temporary twice.
  auto take = [this]() -> asio::awaitable<ServedCopy> {
    ServedCopy copy;
    if (context_.gateway != nullptr) {
      copy.config = context_.gateway->config();
      copy.loads = context_.gateway->loads();
    }
    co_return copy;
  };
  co_return co_await asio::co_spawn(context_.gateway_executor, std::move(take),
                                    asio::use_awaitable);
}

asio::awaitable<HttpReply> ConsoleHandler::config_route(const HttpRequest& request,
                                                      std::string_view path,
                                                      const ConsoleSession& session) {
  if (!role_allows(session.role, Role::admin)) {
    // An attempt to change it is recorded; a look, or a check, changes nothing and is not.
    const bool apply = path == "/api/config" && request.method == "PUT";
    if (apply || (path == "/api/config/confirm" && request.method == "POST"))
      record_config_refused(context_.audit, session.user, apply ? "config" : "config confirm",
                            fmt::format("the {} role may not change the configuration",
                                        role_name(session.role)));
    co_return error_reply(403, "the configuration is for the admin role");
  }
  // What the buses' thread says is served (a reload changes it): when it was loaded, for GET;
  // the configuration and how many loads, to diff an apply and to tell a confirm that came
  // after the applied file's reload. (Not a conditional expression around the co_await: g++ 12
  // destroys its temporary twice.)
  ServedCopy copy;
  std::string loaded_at;
  if (path == "/api/config" && request.method == "GET") {
    const ServedFacts facts = co_await served_facts();
    loaded_at = facts.loaded_at;
  } else if (path == "/api/config" || path == "/api/config/confirm") {
    copy = co_await served_copy();
  }
  const ServedConfig served{copy.config ? &*copy.config : nullptr, copy.loads};
  if (path == "/api/config" && request.method == "GET") co_return config_endpoint_.show(loaded_at);
  co_return config_change(request, path, session, served);
}

HttpReply ConsoleHandler::config_change(const HttpRequest& request, std::string_view path,
                                        const ConsoleSession& session,
                                        const ServedConfig& served) {
  const std::string& method = request.method;
  if (path == "/api/config.toml") {
    if (method != "GET") return error_reply(405, "GET only");
    return config_endpoint_.download();
  }
  if (path == "/api/config/check") {
    if (method != "POST") return error_reply(405, "POST the text to check");
    auto text = parse_config_text(request.body);
    if (!text) return error_reply(400, text.error());
    return config_endpoint_.check(*text);
  }
  if (path == "/api/config/form") {
    if (method == "GET") return config_forms_.keys();
    if (method != "POST") return error_reply(405, "GET the form's keys, or POST a filled form");
    auto form = parse_form_edit_request(request.body);
    if (!form) return error_reply(400, form.error());
    return config_forms_.edit(*form);
  }
  if (path == "/api/config/tables") {
    if (method != "POST") return error_reply(405, "POST the text whose tables to read");
    auto text = parse_config_text(request.body);
    if (!text) return error_reply(400, text.error());
    return config_forms_.tables(*text);
  }
  if (path == "/api/config/confirm") {
    if (method != "POST") return error_reply(405, "POST to confirm the applied configuration");
    // This handler's server serves the [http] the gateway loaded last: the request reached the
    // console through the applied configuration, not through one it replaced.
    const bool through_new_console = served.config != nullptr && served.config->http == config_;
    return config_endpoint_.confirm(session.user, served, through_new_console);
  }
  if (path != "/api/config") return error_reply(404, "no such configuration endpoint");
  if (method != "PUT") return error_reply(405, "GET the configuration, or PUT a new one");
  auto text = parse_config_text(request.body);
  if (!text) {
    record_config_refused(context_.audit, session.user, "config", text.error());
    return error_reply(400, text.error());
  }
  ApplyOutcome outcome;
  HttpReply reply = config_endpoint_.apply(*text, session.user, served, outcome);
  record_apply(context_.audit, session.user, outcome.changes, outcome.result);
  if (reply.status == 200 && context_.reload) context_.reload();
  return reply;
}

}  // namespace tiltgate
