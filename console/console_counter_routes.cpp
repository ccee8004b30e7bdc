// The web console's reset of counters (admin): a sensor's, or a bus's and each of its
// sensors', set back to zero in the gateway, as at a start, and recorded in the audit trail
// (docs/web-console.md, "Counters").
#include <boost/asio/co_spawn.hpp>
#include <boost/asio/use_awaitable.hpp>
#include <fmt/format.h>

#include "console/console_handler.h"
#include "console/console_reply.h"
#include "console/request_guard.h"

namespace tiltgate {

namespace asio = boost::asio;
using json = nlohmann::json;

asio::awaitable<HttpReply> ConsoleHandler::counters_reset(const HttpRequest& request,
                                                          std::string_view path,
                                                          const ConsoleSession& session) {
  const bool bus = path.starts_with(kBusPrefix);
  const std::string_view prefix = bus ? kBusPrefix : kSensorPrefix;
  const auto name = path_name(
      path.substr(prefix.size(), path.size() - prefix.size() - kCountersResetSuffix.size()));
  const std::string_view what = bus ? "bus" : "sensor";
  if (!name) co_return error_reply(404, fmt::format("no such {}", what));
  if (request.method != "POST") co_return error_reply(405, "POST to reset the counters");
  if (!role_allows(session.role, Role::admin)) {
    record(session, *name, "counters", "", "reset", "refused: resetting counters is for the admin role");
    co_return error_reply(403, "resetting counters is for the admin role");
  }
  if (!context_.reset_counters) co_return error_reply(503, "this gateway cannot reset counters");
  const CounterScope scope = bus ? CounterScope::bus : CounterScope::sensor;
  // On the buses' executor, where the counters are kept. Named, not a temporary in the
  // co_await: g++ 12 destroys such a temporary twice.
  auto reset = [&]() -> asio::awaitable<bool> { co_return context_.reset_counters(scope, *name); };
  const bool done = co_await asio::co_spawn(context_.gateway_executor, std::move(reset),
                                            asio::use_awaitable);
  if (!done) co_return error_reply(404, fmt::format("no such {}", what));
  record(session, *name, "counters", "", "reset", "ok");
  co_return json_reply(200, json{{std::string(what), *name}, {"counters", "reset"}});
}

}  // namespace tiltgate
