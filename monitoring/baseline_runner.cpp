#include "monitoring/baseline_runner.h"

#include <nlohmann/json.hpp>

namespace tiltgate::monitoring {

namespace {

using json = nlohmann::json;

BaselineAnswer error_answer(BaselineAnswer::Outcome outcome, const std::string& message) {
  return {outcome, json{{"event", "error"}, {"message", message}}.dump()};
}

std::string baseline_event(const std::string& sensor, const MonitoringService::BaselineNow& now) {
  json event{{"event", "baseline"},
             {"sensor", sensor},
             {"x", now.baseline.x},
             {"y", now.baseline.y},
             {"stored", now.stored.has_value()}};
  if (now.stored) {
    event["by"] = now.stored->by;
    event["unix_ms"] = now.stored->unix_ms;
  }
  return event.dump();
}

// The change a request asks for; none for "show"; an error for what makes no sense.
Expected<std::optional<BaselineChange>, std::string> change_of(const json& asked) {
  const std::string set = asked.value("set", "");
  if (set == "show") return std::optional<BaselineChange>{};
  if (set == "current") return std::optional<BaselineChange>(BaselineChange{});
  if (set == "clear")
    return std::optional<BaselineChange>(BaselineChange{BaselineChange::Kind::clear, {}});
  if (set != "value") return Unexpected(std::string("set must be current, value, clear or show"));
  const auto x = asked.find("x");
  const auto y = asked.find("y");
  if (x == asked.end() || !x->is_number() || (y != asked.end() && !y->is_number()))
    return Unexpected(std::string("a value needs x (and y on two axes), in degrees"));
  BaselineChange change{BaselineChange::Kind::value, {x->get<double>(), 0.0}};
  if (y != asked.end()) change.value.y = y->get<double>();
  if (std::abs(change.value.x) > 180 || std::abs(change.value.y) > 180)
    return Unexpected(std::string("x and y must be within -180..180 degrees"));
  return std::optional<BaselineChange>(change);
}

}  // namespace

bool is_baseline_request(const std::string& request) {
  const json asked = json::parse(request, nullptr, false);
  return asked.is_object() && asked.value("command", "") == "baseline";
}

BaselineAnswer answer_baseline(MonitoringService& monitoring, const std::string& request,
                               const WriteOrigin& by) {
  using Outcome = BaselineAnswer::Outcome;
  const json asked = json::parse(request, nullptr, false);
  if (!asked.is_object()) return error_answer(Outcome::bad_request, "the request is no JSON object");
  const auto named = asked.find("sensor");
  const std::string sensor = named != asked.end() && named->is_string() ? named->get<std::string>() : "";
  if (sensor.empty()) return error_answer(Outcome::bad_request, "name the sensor");
  if (!asked.contains("set") || !asked["set"].is_string())
    return error_answer(Outcome::bad_request, "set must be current, value, clear or show");
  auto change = change_of(asked);
  if (!change) return error_answer(Outcome::bad_request, change.error());
  if (!monitoring.baseline(sensor))
    return error_answer(Outcome::no_sensor, "no sensor \"" + sensor + "\"");
  if (*change) {
    auto set = monitoring.set_baseline(sensor, **change, by);
    if (!set) return error_answer(Outcome::failed, set.error());
  }
  const auto now = monitoring.baseline(sensor);
  if (!now) return error_answer(Outcome::no_sensor, "no sensor \"" + sensor + "\"");
  return {Outcome::done, baseline_event(sensor, *now)};
}

CommandRunner with_baselines(CommandRunner next, MonitoringService& monitoring) {
  return [next = std::move(next), &monitoring](
             std::string request, ServedBus bus, WriteOrigin by,
             std::function<void(std::string)> emit,
             CommandStop& stop) -> boost::asio::awaitable<int> {
    if (!is_baseline_request(request))
      co_return co_await next(std::move(request), std::move(bus), std::move(by), std::move(emit),
                              stop);
    const BaselineAnswer answer = answer_baseline(monitoring, request, by);
    emit(answer.event);
    switch (answer.outcome) {
      case BaselineAnswer::Outcome::done: co_return 0;
      case BaselineAnswer::Outcome::bad_request: co_return 2;
      case BaselineAnswer::Outcome::no_sensor:
      case BaselineAnswer::Outcome::failed: co_return 1;
    }
    co_return 1;
  };
}

}  // namespace tiltgate::monitoring
