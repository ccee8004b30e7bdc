// The web console's routes of a bus: a scan (POST to start it, GET for its progress and what it
// found) and a raw frame, each for the admin role and run by BusActions (console/bus_actions.h),
// with the audit record of each.
#include <algorithm>

#include <fmt/format.h>

#include "console/console_handler.h"
#include "console/console_reply.h"
#include "console/console_requests.h"
#include "console/request_guard.h"

namespace tiltgate {

namespace asio = boost::asio;
using json = nlohmann::json;

namespace {

// What a scan or a raw frame asked for, as its audit record's new value.
std::string asked_text(const ScanRequest& asked) {
  return fmt::format("{}..{}", asked.from, asked.to);
}

std::string asked_text(const RawRequest& asked) {
  return fmt::format("address {} function {} data {}", asked.address, asked.function,
                     asked.data.empty() ? "-" : asked.data);
}

}  // namespace

asio::awaitable<HttpReply> ConsoleHandler::bus_action(const HttpRequest& request,
                                                      std::string_view path,
                                                      const ConsoleSession& session) {
  const bool scan = path.ends_with("/scan");
  const std::string_view rest = path.substr(kBusPrefix.size());
  const auto bus = path_name(rest.substr(0, rest.rfind('/')));
  if (!bus) co_return error_reply(404, "no such bus");
  const ServedFacts facts = co_await served_facts();
  if (std::find(facts.buses.begin(), facts.buses.end(), *bus) == facts.buses.end())
    co_return error_reply(404, "no such bus");
  if (!bus_actions_) {
    // Not one expression with the co_await: g++ 12 destroys its temporaries twice.
    BusActionSetup setup;
    setup.config_path = context_.config_path;
    setup.gateway_executor = context_.gateway_executor;
    setup.served_bus = [gateway = context_.gateway](const std::string& name) {
      return served_bus(*gateway, name);
    };
    setup.families = context_.families;
    setup.commands = context_.commands;
    bus_actions_ = std::make_unique<BusActions>(std::move(setup));
  }
  if (scan && request.method == "GET")
    co_return json_reply(200, bus_actions_->scan_state(*bus));
  if (request.method != "POST") co_return error_reply(405, "POST to start it");
  // Every attempt is one record; a refused one says why, as the reply does, with what was
  // asked when the body said it (docs/web-console.md, "The audit trail").
  const std::string setting = scan ? "scan" : "raw";
  const auto refused = [&](unsigned status, const std::string& why, std::string asked) {
    record(session, *bus, setting, "", std::move(asked), "refused: " + why);
    return error_reply(status, why);
  };
  const bool admin = role_allows(session.role, Role::admin);
  unsigned status = 200;
  if (scan) {
    auto asked = parse_scan_request(request.body);
    const std::string what = asked ? asked_text(*asked) : std::string();
    if (!admin) co_return refused(403, "a scan is for the admin role", what);
    if (!asked) co_return refused(400, asked.error(), what);
    json body = bus_actions_->start_scan(*bus, *asked, session.user, status);
    record(session, *bus, setting, "", what,
           status == 202 ? "ok" : "refused: " + body.value("error", std::string()));
    co_return json_reply(status, body);
  }
  auto asked = parse_raw_request(request.body);
  const std::string what = asked ? asked_text(*asked) : std::string();
  if (!admin) co_return refused(403, "raw frames are for the admin role", what);
  if (!asked) co_return refused(400, asked.error(), what);
  json body = co_await bus_actions_->raw(*bus, *asked, session.user, status);
  // A frame the line carried is recorded by the command's line, for this user, from what it
  // carried and got back when it may have changed the device, and a read not at all
  // (control/served_bus_line.h). One that never reached the line is recorded here, with why.
  if (body["sent"].is_null()) {
    const std::string error = body["error"].is_string() ? body["error"].get<std::string>() : "";
    record(session, *bus, setting, "", what, "error: " + (error.empty() ? "not sent" : error));
  }
  co_return json_reply(status, body);
}

}  // namespace tiltgate
