// Whether this machine's clock can be trusted (issue 57, item 5; docs/operations.md, "The
// clock"): synchronised or not, and the bound on its error, as the kernel holds them for the
// time service (chrony, systemd-timesyncd) that disciplines the clock. The gateway stamps each
// reading with this clock in UTC; a reading taken while it is unsynchronised is flagged.
#pragma once

#include <functional>
#include <optional>
#include <string_view>

struct timex;  // <sys/timex.h>, included by clock_state.cpp only (its macros are many)

namespace tiltgate {

// Why the clock is not synchronised, as far as the kernel says.
enum class ClockProblem {
  none,         // synchronised
  unbounded,    // the kernel's maximum error reached its 16 s limit: no time service has set
                // the clock, it stopped disciplining it (for some 9 hours), or the clock was
                // stepped by hand (settimeofday)
  clock_fault,  // STA_CLOCKERR: the clock hardware reports a fault
  pps_fault,    // the kernel's PPS discipline is on and its signal is missing or unstable
  unreadable,   // adjtimex failed, or a reader could not tell (tests, a machine without it)
};

struct ClockState {
  bool synchronised = false;
  // The bound on the clock's error in milliseconds while synchronised (the kernel's
  // maxerror); none while it is not, when there is no bound to speak of.
  std::optional<double> error_ms;
  // The time service's own estimate of the error (the kernel's esterror): smaller, for the
  // log; none while unsynchronised.
  std::optional<double> estimated_error_ms;
  ClockProblem problem = ClockProblem::unreadable;

  bool operator==(const ClockState&) const = default;
};

// Where a ClockWatch reads the clock's state from: the kernel (read_kernel_clock) in the
// gateway, a made-up sequence in tests.
using ClockReader = std::function<ClockState()>;

// The state the kernel gives now: adjtimex(2) with modes = 0, which only reads (no privilege
// needed; a sandbox that forbids setting the clock still allows it).
ClockState read_kernel_clock();

// What an adjtimex read means (pure; `result` is adjtimex's return value, -1 on failure).
ClockState clock_state_from(const ::timex& kernel, int result);

// The problem in words, for the log: "not synchronised: ...".
std::string_view clock_problem_text(ClockProblem problem);

}  // namespace tiltgate
