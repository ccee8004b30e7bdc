// The checks across a device profile's tables, once each table has been read on its own: read
// blocks that overlap or run past register 65535, values with the same name, values that
// share registers, a value outside every read block, a writable input register, min > max,
// an [identity] that names no value.
#pragma once

#include <optional>
#include <vector>

#include "toml/error_list.h"
#include "modbus_rtu/device_profile.h"

namespace tiltgate::modbus_rtu {

struct LocatedBlock {
  ReadBlock block;
  toml_input::Located where;
  bool read_ok = true;  // read without errors: the checks may rely on its keys
};

struct LocatedValue {
  ProfileValue value;
  toml_input::Located where;
  bool read_ok = true;
};

// The [identity] table as written, where it was.
struct LocatedIdentity {
  ProfileIdentity identity;
  std::optional<toml_input::Located> where;  // none: the profile has no [identity]
};

// `setting_names`: the settings a map file writes by name besides the common block's (every
// model's own); a value may take none of them.
void check_profile(const std::vector<LocatedBlock>& blocks, const std::vector<LocatedValue>& values,
                   std::span<const std::string_view> setting_names, toml_input::ErrorList& errors);

// Each name [identity] gives must be one of the values' (the closest one suggested).
void check_identity(const LocatedIdentity& identity, const std::vector<LocatedValue>& values,
                    toml_input::ErrorList& errors);

}  // namespace tiltgate::modbus_rtu
