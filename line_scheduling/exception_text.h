// What a caught exception says, for a log line: its what(), or that it was not a
// std::exception. Used where a bus logs a failure it goes on after (line_scheduling/shared_line.h,
// line_scheduling/bus_scheduler.h).
#pragma once

#include <exception>
#include <string>

namespace tiltgate {

inline std::string exception_text(const std::exception_ptr& failure) {
  try {
    std::rethrow_exception(failure);
  } catch (const std::exception& e) {
    return e.what();
  } catch (...) {
  }
  return "an exception that is not a std::exception";
}

}  // namespace tiltgate
