#include "clock/clock_state.h"

#include <sys/timex.h>

namespace tiltgate {

namespace {

// The kernel's bound on maxerror, in microseconds (kernel/time/ntp.c NTP_PHASE_LIMIT, 16 s):
// second_overflow() adds 500 us (MAXFREQ, 500 ppm) to maxerror every second, and once it
// passes this limit clamps it there and sets STA_UNSYNC. The kernel starts there at boot, and
// a step of the clock (settimeofday, ADJ_SETOFFSET: ntp_clear()) puts it back there.
constexpr long long kPhaseLimitUs = 16'000'000;

// The status bits besides STA_UNSYNC that make adjtimex return TIME_ERROR (kernel/time/ntp.c,
// is_error_status(); adjtimex(2), RETURN VALUE).
ClockProblem error_status_problem(int status) {
  if (status & STA_CLOCKERR) return ClockProblem::clock_fault;
  const bool pps_lost = (status & (STA_PPSFREQ | STA_PPSTIME)) && !(status & STA_PPSSIGNAL);
  const bool pps_jitter = (status & STA_PPSTIME) && (status & STA_PPSJITTER);
  const bool pps_wander =
      (status & STA_PPSFREQ) && (status & (STA_PPSWANDER | STA_PPSERROR));
  if (pps_lost || pps_jitter || pps_wander) return ClockProblem::pps_fault;
  return ClockProblem::none;
}

// The kernel keeps both errors in microseconds, whatever STA_NANO says (adjtimex(2)).
template <class Microseconds>
double ms_from_us(Microseconds us) {
  return static_cast<double>(us) / 1000.0;
}

}  // namespace

// What chrony and systemd-timesyncd leave in the kernel, and so what this reads:
//
// - chrony (sys_timex.c, set_sync_status) writes maxerror and esterror after every clock
//   update: its root distance and its error estimate, both 16 s while it is not synchronised.
//   On Linux it clears STA_UNSYNC only with `rtcsync` in chrony.conf (Debian's has it): without
//   it STA_UNSYNC stays set, and adjtimex returns TIME_ERROR, while the clock is synchronised.
// - systemd-timesyncd (timesyncd-manager.c, manager_adjust_clock) sets maxerror and esterror to
//   0 at every sync and clears STA_UNSYNC, unless the RTC keeps local time, when it leaves
//   STA_UNSYNC set so the kernel does not write the RTC.
// - Between updates the kernel adds 500 ppm to maxerror; a service that stopped (no server
//   reachable, stopped by hand) leaves the clock "synchronised" with a growing bound for some
//   9 hours ((16 s - its last bound) / 500 us per second), after which the kernel itself says
//   unsynchronised.
//
// So, as systemd's timedated decides what `timedatectl` shows as "System clock synchronized"
// (time-util.c ntp_synced(), systemd PR #13245): synchronised while maxerror is below 16 s,
// whatever STA_UNSYNC says. A TIME_ERROR for another reason (a clock hardware fault, a PPS
// discipline without its signal) means the clock is not to be trusted either.
//
// error_ms is maxerror, not esterror: it is the bound the time service and the kernel stand
// behind (the time is within it, at its worst), the one a reading's time can be signed off
// against, and it grows while nobody disciplines the clock; esterror is the service's expected
// error, smaller, and the kernel leaves it as it was set.
ClockState clock_state_from(const ::timex& kernel, int result) {
  ClockState state;
  if (result < 0) return state;  // unreadable
  if (result == TIME_ERROR) {
    const ClockProblem fault = error_status_problem(kernel.status);
    if (fault != ClockProblem::none) {
      state.problem = fault;
      return state;
    }
    // STA_UNSYNC alone: left set on purpose by chrony without rtcsync and by timesyncd with a
    // local-time RTC; maxerror decides.
  }
  if (kernel.maxerror < 0 || kernel.maxerror >= kPhaseLimitUs) {
    state.problem = ClockProblem::unbounded;
    return state;
  }
  state.synchronised = true;
  state.problem = ClockProblem::none;
  state.error_ms = ms_from_us(kernel.maxerror);
  if (kernel.esterror >= 0 && kernel.esterror < kPhaseLimitUs)
    state.estimated_error_ms = ms_from_us(kernel.esterror);
  return state;
}

ClockState read_kernel_clock() {
  ::timex kernel{};
  kernel.modes = 0;  // read only
  const int result = ::adjtimex(&kernel);
  return clock_state_from(kernel, result);
}

std::string_view clock_problem_text(ClockProblem problem) {
  switch (problem) {
    case ClockProblem::none: return "synchronised";
    case ClockProblem::unbounded:
      return "the kernel's maximum-error bound reached 16 s: no time service (chrony, "
             "systemd-timesyncd) has synchronised the clock since it booted or was set by hand, "
             "or none has for some 9 hours";
    case ClockProblem::clock_fault:
      return "the kernel reports a clock hardware fault (STA_CLOCKERR)";
    case ClockProblem::pps_fault:
      return "the kernel's PPS discipline is on but its signal is missing or unstable";
    case ClockProblem::unreadable:
      return "the kernel's clock state cannot be read: adjtimex was refused (a systemd sandbox with "
             "ProtectClock=yes or without clock_adjtime in SystemCallFilter denies it)";
  }
  return "unknown";
}

}  // namespace tiltgate
