#include "control/served_bus_line.h"

#include <algorithm>
#include <fmt/format.h>

#include "audit/audit_trail.h"
#include "gateway/gateway.h"

namespace tiltgate {

namespace asio = boost::asio;

std::vector<ServedBus> served_buses(const Gateway& gateway) {
  const Config& config = gateway.config();
  std::vector<ServedBus> served;
  const std::vector<std::shared_ptr<BusScheduler>> schedulers = gateway.schedulers();
  for (std::size_t i = 0; i < schedulers.size(); ++i)
    served.push_back({config.buses[i], schedulers[i],
                      find_protocol(gateway.families(), config.buses[i].protocol).protocol,
                      gateway.black_box(config.buses[i].name)});
  return served;
}

std::optional<ServedBus> served_bus(const Gateway& gateway, const std::string& name) {
  for (ServedBus& bus : served_buses(gateway))
    if (bus.config.name == name) return std::move(bus);
  return std::nullopt;
}

ServedBusLine::ServedBusLine(ServedBus bus, WriteOrigin by)
    : bus_(std::move(bus)), by_(std::move(by)) {}

ServedBusLine::~ServedBusLine() {
  record_pending();
  // A command that went away mid re-address must not leave a sensor unpolled.
  for (const std::uint32_t address : held_) bus_.scheduler->release(address);
}

asio::awaitable<Expected<Done, LineError>> ServedBusLine::transact(LineRequest request) {
  co_return co_await transact_in_turns(
      std::move(request), defaults_, timing_,
      [this](const LineRequest& one) { return attempt(one); });
}

bool ServedBusLine::note_asked(control::CarriedChange asked) {
  if (change_ && !control::same_request(*change_, asked)) record_pending();
  change_ = std::move(asked);
  // [audit] when_full = "refuse": no change the trail cannot keep on disk.
  if (AuditTrail* trail = bus_.scheduler->audit(); trail != nullptr && !trail->accepts_changes()) {
    change_->result = fmt::format("refused: {}", kAuditRefusesChanges);
    change_->unix_ms = control::now_unix_ms();
    record_pending();
    return false;
  }
  return true;
}

asio::awaitable<Expected<Done, LineError>> ServedBusLine::attempt(const LineRequest& request) {
  timing_ = LineTiming{};
  audit_refused_ = false;
  if (stopped_) co_return Unexpected{LineError::cancelled};
  std::optional<control::CarriedChange> asked;
  if (bus_.protocol != nullptr) asked = control::change_asked(*bus_.protocol, request.bytes);
  const bool changing = asked.has_value();
  if (changing && !note_asked(std::move(*asked))) {
    audit_refused_ = true;
    co_return Unexpected{LineError::cancelled};
  }
  ++stats_.attempts;
  const SteadyClock::time_point deadline = SteadyClock::now() + kQueueDeadline;
  CommandExchangeResult result = co_await bus_.scheduler->exchange_for_command(request, deadline);
  timing_ = result.timing;
  generation_ = result.generation;
  if (changing && change_) {
    control::CarriedEnd ended;
    if (!result.done) ended.error = result.done.error();
    ended.busy = result.expired;
    const FramerReport framed = request.framer ? request.framer->report() : FramerReport{};
    change_->result = control::carried_result(*bus_.protocol, ended, request.framer != nullptr,
                                              framed.reply);
    change_->unix_ms = control::now_unix_ms();
  }
  if (!result.done && result.done.error() == LineError::timeout) ++stats_.timeouts;
  co_return result.done;
}

void ServedBusLine::record_pending() {
  if (change_)
    bus_.scheduler->note_carried(change_->address, std::move(change_->function),
                                 std::move(change_->data), std::move(change_->result),
                                 change_->unix_ms, by_);
  change_.reset();
}

std::optional<std::string> ServedBusLine::hold(std::uint32_t address) {
  const auto sensor = bus_.scheduler->hold(address, SteadyClock::now() + kMaxHold);
  if (sensor) held_.push_back(address);
  return sensor;
}

std::optional<std::string> ServedBusLine::follow(std::uint32_t from, std::uint32_t to) {
  if (change_ && change_->address != from) record_pending();
  change_.reset();
  std::erase(held_, from);
  return bus_.scheduler->follow_address(from, to, by_);
}

std::optional<std::string> ServedBusLine::setting_changed(std::uint32_t address,
                                                          WriteTarget setting, double value,
                                                          std::string result) {
  // The engine's report of the change its transaction carried: one record, the setting's.
  change_.reset();
  return bus_.scheduler->note_setting(address, setting, value, std::move(result), by_);
}

}  // namespace tiltgate
