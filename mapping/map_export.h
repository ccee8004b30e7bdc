// `tiltgate map`: the register maps as CSV for PLC tag databases, or as a Markdown table for a
// commissioning report.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "mapping/register_map.h"

namespace tiltgate {

struct UnitMap {
  std::uint8_t unit_id;
  std::string sensor;  // sensor name, for headings
  std::string model;
  const RegisterMap* map;
  WordOrder word_order = WordOrder::big;  // [server] word_order, for points without their own
  std::uint16_t port = 0;  // the Modbus TCP port serving the unit; 0: not shown
  std::string note{};      // a paragraph under the unit's heading (Markdown only)
};

// Header: unit_id,name,table,address,words,type,access,units,description,scale,offset,word_order,
// port,plc_address,role. word_order is the byte layout (ABCD, CDAB, BADC, DCBA; AB or BA for 16-bit
// values), empty for bits and strings; port is the TCP port serving the unit (empty when not
// known); plc_address is plc_number() (30001 style), last so that the columns before it keep
// their places in an import template made before it was added; role (after it, for the same
// reason) is who may change a writable point's setting, operator or admin, empty for a
// read-only point.
std::string export_csv(const std::vector<UnitMap>& units);
std::string export_markdown(const std::vector<UnitMap>& units);

// The 1-based number many PLC tools show: 0xxxx coils, 1xxxx discrete inputs, 3xxxx input
// registers, 4xxxx holding registers (e.g. input register 0 is 30001).
std::string plc_number(RegisterTable table, std::uint16_t address);

}  // namespace tiltgate
