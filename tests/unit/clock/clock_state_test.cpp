// What an adjtimex read says of the clock (clock/clock_state.h), from made-up kernel states as
// chrony and systemd-timesyncd leave them (clock/clock_state.cpp says which).
#include <doctest/doctest.h>
#include <sys/timex.h>

#include "clock/clock_state.h"

using namespace tiltgate;

namespace {

// The kernel's state: status bits, maxerror and esterror in microseconds.
::timex kernel(int status, long maxerror_us, long esterror_us) {
  ::timex t{};
  t.status = status;
  t.maxerror = maxerror_us;
  t.esterror = esterror_us;
  return t;
}

}  // namespace

TEST_CASE("clock: synchronised by timesyncd, the bound as it grew since its last sync") {
  // timesyncd set maxerror to 0 and cleared STA_UNSYNC; 24 s later the kernel added 12 ms.
  const ClockState state = clock_state_from(kernel(STA_PLL, 12'000, 0), TIME_OK);
  CHECK(state.synchronised);
  CHECK(state.problem == ClockProblem::none);
  REQUIRE(state.error_ms.has_value());
  CHECK(*state.error_ms == doctest::Approx(12.0));
  CHECK(state.estimated_error_ms == doctest::Approx(0.0));
}

TEST_CASE("clock: synchronised by chrony, error_ms is maxerror (the bound), not esterror") {
  const ClockState state = clock_state_from(kernel(STA_PLL | STA_NANO, 23'456, 1'250), TIME_OK);
  CHECK(state.synchronised);
  CHECK(*state.error_ms == doctest::Approx(23.456));
  CHECK(*state.estimated_error_ms == doctest::Approx(1.25));
}

TEST_CASE("clock: TIME_ERROR from STA_UNSYNC alone is synchronised while maxerror is below 16 s") {
  // chrony without rtcsync, or timesyncd with the RTC in local time, leave STA_UNSYNC set so
  // the kernel does not write the RTC; timedatectl says synchronised, and so do we.
  const ClockState state = clock_state_from(kernel(STA_UNSYNC, 40'000, 2'000), TIME_ERROR);
  CHECK(state.synchronised);
  CHECK(*state.error_ms == doctest::Approx(40.0));
}

TEST_CASE("clock: never synchronised since boot: maxerror at its 16 s limit, no bound") {
  // What this kernel starts with, and what a step of the clock by hand leaves (ntp_clear()).
  const ClockState state =
      clock_state_from(kernel(STA_UNSYNC, 16'000'000, 16'000'000), TIME_ERROR);
  CHECK_FALSE(state.synchronised);
  CHECK(state.problem == ClockProblem::unbounded);
  CHECK_FALSE(state.error_ms.has_value());
  CHECK_FALSE(state.estimated_error_ms.has_value());
}

TEST_CASE("clock: a large maxerror just under the limit is still synchronised, with that bound") {
  // The time service stopped some 8.8 hours ago: the kernel has not given up yet.
  const ClockState late = clock_state_from(kernel(STA_PLL, 15'999'999, 0), TIME_OK);
  CHECK(late.synchronised);
  CHECK(*late.error_ms == doctest::Approx(15'999.999));
  // At the limit it is not, whatever the status bits say (the kernel sets STA_UNSYNC then).
  CHECK_FALSE(clock_state_from(kernel(STA_PLL, 16'000'000, 0), TIME_OK).synchronised);
  CHECK_FALSE(clock_state_from(kernel(STA_PLL, 20'000'000, 0), TIME_OK).synchronised);
}

TEST_CASE("clock: chrony unsynchronised writes 16 s into both errors") {
  const ClockState state =
      clock_state_from(kernel(STA_UNSYNC | STA_PLL, 16'000'000, 16'000'000), TIME_ERROR);
  CHECK_FALSE(state.synchronised);
  CHECK(state.problem == ClockProblem::unbounded);
}

TEST_CASE("clock: a TIME_ERROR for a clock fault or a PPS discipline without its signal is unsynchronised") {
  const ClockState fault = clock_state_from(kernel(STA_CLOCKERR, 5'000, 100), TIME_ERROR);
  CHECK_FALSE(fault.synchronised);
  CHECK(fault.problem == ClockProblem::clock_fault);
  CHECK_FALSE(fault.error_ms.has_value());
  const ClockState pps = clock_state_from(kernel(STA_PPSTIME | STA_PLL, 5'000, 100), TIME_ERROR);
  CHECK_FALSE(pps.synchronised);
  CHECK(pps.problem == ClockProblem::pps_fault);
  const ClockState jitter = clock_state_from(
      kernel(STA_PPSTIME | STA_PPSSIGNAL | STA_PPSJITTER, 5'000, 100), TIME_ERROR);
  CHECK(jitter.problem == ClockProblem::pps_fault);
  // With its signal and no jitter, PPS is no fault.
  CHECK(clock_state_from(kernel(STA_PPSTIME | STA_PPSSIGNAL, 5'000, 100), TIME_OK).synchronised);
}

TEST_CASE("clock: a leap second announced or in progress is no problem") {
  CHECK(clock_state_from(kernel(STA_PLL | STA_INS, 3'000, 0), TIME_INS).synchronised);
  CHECK(clock_state_from(kernel(STA_PLL, 3'000, 0), TIME_OOP).synchronised);
  CHECK(clock_state_from(kernel(STA_PLL, 3'000, 0), TIME_WAIT).synchronised);
}

TEST_CASE("clock: adjtimex failing (a sandbox that denies it) is unsynchronised and unreadable") {
  const ClockState state = clock_state_from(kernel(0, 1'000, 0), -1);
  CHECK_FALSE(state.synchronised);
  CHECK(state.problem == ClockProblem::unreadable);
  CHECK_FALSE(state.error_ms.has_value());
  CHECK(clock_problem_text(state.problem).find("ProtectClock") != std::string_view::npos);
  CHECK(ClockState{} == state);  // what a reader that cannot tell returns
}

TEST_CASE("clock: the kernel's own state reads, synchronised or not, with a bound only when synchronised") {
  const ClockState state = read_kernel_clock();
  CHECK(state.synchronised == state.error_ms.has_value());
  CHECK(state.synchronised == (state.problem == ClockProblem::none));
}
