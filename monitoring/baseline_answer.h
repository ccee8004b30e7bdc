// What a baseline request (monitoring/baseline_runner.h) was answered: the "baseline" event
// (the baseline in force after it), or the "error" event and why. Its own header, so that a
// door that asks (the web console) needs nothing of the monitoring's but this.
#pragma once

#include <string>

namespace tiltgate::monitoring {

struct BaselineAnswer {
  enum class Outcome {
    done,
    bad_request,  // a request that makes no sense (no sensor named, an unknown `set`, ...)
    no_sensor,    // no such sensor is served
    failed,       // asked right, but could not be done (no reading yet, a disk refusing)
  };
  Outcome outcome = Outcome::done;
  std::string event;  // JSON
};

}  // namespace tiltgate::monitoring
