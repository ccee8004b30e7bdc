#include "control/setting_claim.h"

#include <fmt/format.h>

namespace tiltgate::control {

CarriedOutcome carried_outcome(const Ended& ended) {
  if (ended.busy) return CarriedOutcome::not_sent;
  if (!ended.error) return CarriedOutcome::answered;
  return *ended.error == LineError::timeout ? CarriedOutcome::timed_out
                                            : CarriedOutcome::not_sent;
}

std::optional<std::string> setting_claim_refusal(CarriedOutcome carried,
                                                 const SettingChanged& claim) {
  switch (carried) {
    case CarriedOutcome::none:
      return "a setting reported with no transaction of this session carried before it";
    case CarriedOutcome::not_sent:
      return "a setting reported after a transaction the device was never asked";
    case CarriedOutcome::timed_out:
      if (!claim.timeout) return "a setting reported answered after a transaction that timed out";
      return std::nullopt;
    case CarriedOutcome::answered:
      if (claim.timeout) return "a setting reported timed out after a transaction answered";
      return std::nullopt;
  }
  return "a setting reported after an unknown outcome";
}

std::string setting_result(const SettingChanged& changed) {
  if (changed.nak) return fmt::format("nak 0x{:02X}", *changed.nak);
  return changed.timeout ? "timeout" : "ack";
}

}  // namespace tiltgate::control
