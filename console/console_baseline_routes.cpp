// The web console's baseline of a sensor (docs/monitoring.md, "Baseline and displacement"):
// GET shows the baseline in force and who set it (any role); POST sets it to the sensor's
// current reading or to given angles, or clears it (admin: every relative angle, displacement
// and displacement alarm is measured from it). The request and its answer are those of
// `tiltgate baseline` (monitoring/baseline_runner.h); the monitoring records the change in the
// audit trail as the console's, with the user, and as an event.
#include <boost/asio/co_spawn.hpp>
#include <boost/asio/use_awaitable.hpp>
#include <nlohmann/json.hpp>

#include "console/console_handler.h"
#include "console/console_reply.h"
#include "console/request_guard.h"

namespace tiltgate {

namespace asio = boost::asio;
using json = nlohmann::json;

namespace {

unsigned status_of(monitoring::BaselineAnswer::Outcome outcome) {
  using Outcome = monitoring::BaselineAnswer::Outcome;
  switch (outcome) {
    case Outcome::done: return 200;
    case Outcome::bad_request: return 400;
    case Outcome::no_sensor: return 404;
    case Outcome::failed: return 409;
  }
  return 500;
}

}  // namespace

asio::awaitable<HttpReply> ConsoleHandler::baseline_route(const HttpRequest& request,
                                                          std::string_view path,
                                                          const ConsoleSession& session) {
  const auto name = path_name(
      path.substr(kSensorPrefix.size(), path.size() - kSensorPrefix.size() - kBaselineSuffix.size()));
  if (!name) co_return error_reply(404, "no such sensor");
  const bool change = request.method == "POST";
  if (!change && request.method != "GET")
    co_return error_reply(405, "GET a sensor's baseline, or POST one to change it");
  json asked = json::object();
  if (change) {
    asked = json::parse(request.body, nullptr, false);
    if (!asked.is_object())
      co_return error_reply(400, "send {\"set\": \"current\"}, {\"set\": \"value\", \"x\": X, "
                                 "\"y\": Y} or {\"set\": \"clear\"}");
    if (asked.value("set", json()) == json("show"))
      co_return error_reply(400, "GET shows the baseline; POST changes it");
    if (!role_allows(session.role, Role::admin)) {
      record(session, *name, "baseline", "", asked.dump(),
             "refused: changing a baseline is for the admin role");
      co_return error_reply(403, "changing a baseline is for the admin role");
    }
  } else {
    asked["set"] = "show";
  }
  asked["command"] = "baseline";
  asked["sensor"] = *name;
  if (!context_.baseline) co_return error_reply(503, "this gateway keeps no baselines");
  // On the buses' executor, where the sensors' processing is. Named, not a temporary in the
  // co_await: g++ 12 destroys such a temporary twice.
  const std::string text = asked.dump();
  auto answer_it = [&]() -> asio::awaitable<monitoring::BaselineAnswer> {
    co_return context_.baseline(text, WriteOrigin{"console", session.user});
  };
  const monitoring::BaselineAnswer answer =
      co_await asio::co_spawn(context_.gateway_executor, std::move(answer_it), asio::use_awaitable);
  json event = json::parse(answer.event, nullptr, false);
  if (answer.outcome != monitoring::BaselineAnswer::Outcome::done)
    co_return error_reply(status_of(answer.outcome), event.value("message", "refused"));
  event.erase("event");
  co_return json_reply(200, event);
}

}  // namespace tiltgate
