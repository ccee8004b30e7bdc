#include "settings/setting_outcome.h"

#include <fmt/format.h>

namespace tiltgate {

SettingOutcome outcome_of(const WriteError& error) {
  using Result = SettingOutcome::Result;
  SettingOutcome outcome;
  outcome.detail = error.detail;
  switch (error.kind) {
    case WriteErrorKind::no_response:
      outcome.result = Result::timeout;
      return outcome;
    case WriteErrorKind::bad_value:
    case WriteErrorKind::not_supported:
      outcome.result = Result::refused;
      return outcome;
    case WriteErrorKind::device_exception:
      outcome.result = Result::nak;
      outcome.code = error.device_exception;
      return outcome;
    case WriteErrorKind::busy:
      // Busy without the sensor's NAK: the bus could not start the write in time.
      outcome.result = error.nak ? Result::nak : Result::timeout;
      outcome.code = error.nak;
      return outcome;
    case WriteErrorKind::rejected:
    case WriteErrorKind::refused:
      outcome.result = Result::nak;
      outcome.code = error.nak;
      return outcome;
  }
  return outcome;
}

std::string audit_result(const SettingOutcome& outcome) {
  using Result = SettingOutcome::Result;
  switch (outcome.result) {
    case Result::ack: return "ack";
    case Result::nak: return outcome.code ? fmt::format("nak 0x{:02X}", *outcome.code) : "nak";
    case Result::timeout: return "timeout";
    case Result::refused: return "refused: " + outcome.detail;
  }
  return "refused: " + outcome.detail;
}

}  // namespace tiltgate
