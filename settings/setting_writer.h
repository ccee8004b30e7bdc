// A DCMD's setting write (sparkplug/edge_node_session.h Write) carried out as a Modbus write
// of the same setting is: planned against the sensor's register map with the same range
// checks (mapping/map_access.h plan_point_write), queued on the sensor's bus as one
// SensorWrite (gateway/sensor_write.h) with [server] write_timeout, and answered only once the
// sensor acknowledged it or the write failed.
//
// Threads: the gateway's event loop (the buses' executor).
#pragma once

#include <boost/asio/awaitable.hpp>
#include <optional>
#include <string>

#include "driver/expected.h"
#include "driver/family.h"
#include "gateway/gateway.h"
#include "sparkplug/edge_node_session.h"

namespace tiltgate::sparkplug {

class SettingWriter {
 public:
  SettingWriter(const Gateway& gateway, FamilyList families);

  // None once the sensor took the value; otherwise why not, for the log. (Not an Expected:
  // co_spawn wants a result it can default-construct.)
  boost::asio::awaitable<std::optional<std::string>> write(Write write) const;

 private:
  const Gateway& gateway_;
  FamilyList families_;
};

}  // namespace tiltgate::sparkplug
