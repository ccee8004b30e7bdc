#include "control/control_session.h"

#include <fmt/format.h>

#include "audit/audit_trail.h"
#include "control/control_relay.h"

namespace tiltgate {

namespace asio = boost::asio;

namespace {

std::string formatted(const control::GatewayMessage& message) { return control::format(message); }

std::string followed(const ServedBusLine& line, const std::optional<std::string>& sensor) {
  return formatted(control::Followed{sensor ? line.bus().config.name + "/" + *sensor : ""});
}

}  // namespace

std::string ControlSession::version(const control::CommandMessage* message, bool& done) {
  const auto* said = message ? std::get_if<control::Version>(message) : nullptr;
  if (said != nullptr && said->protocol == control::kProtocolVersion) {
    versions_agree_ = true;
    return formatted(control::Version{control::kProtocolVersion, TILTGATE_VERSION});
  }
  done = true;
  return control::version_mismatch(TILTGATE_VERSION, said ? std::optional(*said) : std::nullopt);
}

// `as WHO`: the session's changes are recorded as WHO's from now on. Only a process of the
// gateway's own user (the web console) may say so: anyone else could hide behind a name.
std::string ControlSession::act_for(const control::ActingFor& acting) {
  if (!setup_.own_user)
    return formatted(control::Refused{"as: only a process of the gateway's own user may act "
                                      "for someone else"});
  setup_.by.who = acting.who + " (via the control socket)";
  if (line_) line_->act_for(setup_.by);
  return formatted(control::Followed{});
}

std::string ControlSession::hello(const control::Hello& hello) {
  const ServedBus* bus = setup_.find_bus(hello.port);
  if (bus == nullptr)
    return formatted(control::Refused{fmt::format("the gateway has no bus on {} (its buses: {})",
                                                  hello.port, setup_.bus_list())});
  line_ = std::make_unique<ServedBusLine>(*bus, setup_.by);
  return formatted(control::BusGranted{bus->config.name, bus->config.protocol, bus->config.baud});
}

asio::awaitable<std::string> ControlSession::transact(const control::Transact& transact,
                                                      bool& done) {
  ControlRelayFramer relay(socket_, input_);
  LineRequest request{transact.bytes,    transact.address_bytes,
                      transact.expects_reply ? &relay : nullptr,
                      transact.timeout,  transact.retries,
                      transact.settle,   transact.late_guard};
  const Expected<Done, LineError> result = co_await line_->transact(std::move(request));
  if (line_->last_audit_refused()) {
    carried_ = control::CarriedOutcome::not_sent;
    co_return formatted(control::Refused{std::string(kAuditRefusesChanges)});
  }
  control::Ended ended;
  if (!result) ended.error = result.error();
  ended.busy = line_->last_busy();
  ended.timing = line_->last_timing();
  ended.generation = line_->generation();
  carried_ = control::carried_outcome(ended);
  done = relay.broken();  // the command stopped answering mid-transaction
  co_return formatted(ended);
}

std::string ControlSession::setting(const control::SettingChanged& changed) {
  // Recorded either way; only a report a transaction stands behind changes what is shown.
  const auto refusal = control::setting_claim_refusal(std::exchange(carried_, {}), changed);
  const auto sensor = line_->setting_changed(
      changed.address, WriteTarget{changed.setting}, changed.value,
      refusal ? "refused: " + *refusal : control::setting_result(changed), !refusal);
  return refusal ? formatted(control::Refused{"setting: " + *refusal}) : followed(*line_, sensor);
}

asio::awaitable<std::string> ControlSession::answer(const std::string& line, bool& done) {
  auto message = control::parse_command(line);
  // A report after the transaction names its change: one record, the report's.
  const bool keeps_change =
      message && (std::holds_alternative<control::SettingChanged>(*message) ||
                  std::holds_alternative<control::Follow>(*message) ||
                  std::holds_alternative<control::Transact>(*message));
  if (line_ && !keeps_change) line_->record_pending();
  if (!versions_agree_) co_return version(message ? &*message : nullptr, done);
  if (!message) {
    done = true;
    co_return formatted(control::Refused{message.error()});
  }
  if (const auto* acting = std::get_if<control::ActingFor>(&*message)) co_return act_for(*acting);
  if (const auto* asked = std::get_if<control::Hello>(&*message)) co_return hello(*asked);
  if (!line_) {
    done = true;
    co_return formatted(control::Refused{"ask for a bus first (hello PORT)"});
  }
  if (const auto* carried = std::get_if<control::Transact>(&*message))
    co_return co_await transact(*carried, done);
  if (const auto* follow = std::get_if<control::Follow>(&*message))
    co_return followed(*line_, line_->follow(follow->from, follow->to));
  if (const auto* hold = std::get_if<control::Hold>(&*message))
    co_return followed(*line_, line_->hold(hold->address));
  if (const auto* changed = std::get_if<control::SettingChanged>(&*message))
    co_return setting(*changed);
  if (const auto* release = std::get_if<control::Release>(&*message)) {
    line_->release(release->address);
    co_return formatted(control::Followed{});
  }
  done = true;
  co_return formatted(control::Refused{"a framer's answer outside a transaction"});
}

}  // namespace tiltgate
