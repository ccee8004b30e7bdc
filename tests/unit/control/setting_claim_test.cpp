// Whether the gateway takes a command's `setting` report (control/setting_claim.h): only right
// after a transaction of the session that ended as the report says.
#include <doctest/doctest.h>

#include "control/setting_claim.h"

using namespace tiltgate;
using namespace tiltgate::control;

TEST_CASE("a setting report is taken only after a transaction that ended as it says") {
  const SettingChanged ack{223, 1, 2, std::nullopt, false};
  const SettingChanged nak{223, 1, 2, std::uint8_t{3}, false};
  const SettingChanged timeout{223, 1, 2, std::nullopt, true};
  CHECK_FALSE(setting_claim_refusal(CarriedOutcome::answered, ack));
  CHECK_FALSE(setting_claim_refusal(CarriedOutcome::answered, nak));
  CHECK_FALSE(setting_claim_refusal(CarriedOutcome::timed_out, timeout));
  CHECK(setting_claim_refusal(CarriedOutcome::none, ack));
  CHECK(setting_claim_refusal(CarriedOutcome::none, timeout));
  CHECK(setting_claim_refusal(CarriedOutcome::not_sent, ack));
  CHECK(setting_claim_refusal(CarriedOutcome::timed_out, ack));
  CHECK(setting_claim_refusal(CarriedOutcome::answered, timeout));
}

namespace {

Ended ended_with(std::optional<LineError> error) {
  Ended ended;
  ended.error = error;
  return ended;
}

}  // namespace

TEST_CASE("a transaction's end as the session counts it: answered, timed out, or never sent") {
  CHECK(carried_outcome(ended_with(std::nullopt)) == CarriedOutcome::answered);
  CHECK(carried_outcome(ended_with(LineError::timeout)) == CarriedOutcome::timed_out);
  CHECK(carried_outcome(ended_with(LineError::io)) == CarriedOutcome::not_sent);
  CHECK(carried_outcome(ended_with(LineError::overloaded)) == CarriedOutcome::not_sent);
  Ended busy;
  busy.busy = true;
  CHECK(carried_outcome(busy) == CarriedOutcome::not_sent);
}
