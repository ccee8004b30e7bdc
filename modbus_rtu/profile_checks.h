// The checks across a device profile's tables, once each table has been read on its own: read
// blocks that overlap or run past register 65535, values with the same name, values that
// share registers, a value outside every read block, a writable input register, min > max.
#pragma once

#include <vector>

#include "config/error_list.h"
#include "modbus_rtu/device_profile.h"

namespace tiltgate::modbus_rtu {

struct LocatedBlock {
  ReadBlock block;
  config::Located where;
  bool read_ok = true;  // read without errors: the checks may rely on its keys
};

struct LocatedValue {
  ProfileValue value;
  config::Located where;
  bool read_ok = true;
};

void check_profile(const std::vector<LocatedBlock>& blocks, const std::vector<LocatedValue>& values,
                   config::ErrorList& errors);

}  // namespace tiltgate::modbus_rtu
