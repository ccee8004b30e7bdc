#include "mapping/point_types.h"

#include <array>

namespace tiltgate {
namespace {

constexpr std::array<Named<RegisterTable>, 4> kTables{{
    {"coil", RegisterTable::coil},
    {"discrete", RegisterTable::discrete},
    {"input", RegisterTable::input},
    {"holding", RegisterTable::holding},
}};

constexpr std::array<Named<PointType>, 8> kTypes{{
    {"bool", PointType::boolean},
    {"uint16", PointType::uint16},
    {"int16", PointType::int16},
    {"uint32", PointType::uint32},
    {"int32", PointType::int32},
    {"float32", PointType::float32},
    {"float64", PointType::float64},
    {"string", PointType::string},
}};

constexpr std::array<Named<RegisterOrder>, 4> kOrders{{
    {"ABCD", RegisterOrder::abcd},
    {"CDAB", RegisterOrder::cdab},
    {"BADC", RegisterOrder::badc},
    {"DCBA", RegisterOrder::dcba},
}};

constexpr std::array<Named<AngleUnit>, 3> kAngleUnits{{
    {"deg", AngleUnit::degrees},
    {"mrad", AngleUnit::milliradians},
    {"percent", AngleUnit::percent_grade},
}};

constexpr std::array<Named<Rounding>, 4> kRoundings{{
    {"nearest", Rounding::nearest},
    {"floor", Rounding::floor},
    {"ceil", Rounding::ceil},
    {"truncate", Rounding::truncate},
}};

constexpr std::array<Named<SettingRole>, 2> kRoles{{
    {"operator", SettingRole::operator_},
    {"admin", SettingRole::admin},
}};

}  // namespace

RegisterOrder register_order(WordOrder server) {
  return server == WordOrder::big ? RegisterOrder::abcd : RegisterOrder::cdab;
}

bool swaps_words(RegisterOrder order) {
  return order == RegisterOrder::cdab || order == RegisterOrder::dcba;
}

bool swaps_bytes(RegisterOrder order) {
  return order == RegisterOrder::badc || order == RegisterOrder::dcba;
}

std::span<const Named<RegisterTable>> table_names() { return kTables; }
std::span<const Named<PointType>> type_names() { return kTypes; }
std::span<const Named<RegisterOrder>> order_names() { return kOrders; }
std::span<const Named<AngleUnit>> angle_unit_names() { return kAngleUnits; }
std::span<const Named<Rounding>> rounding_names() { return kRoundings; }
std::span<const Named<SettingRole>> role_names() { return kRoles; }

const char* to_string(RegisterTable table) { return name_of(table_names(), table).data(); }
const char* to_string(PointType type) { return name_of(type_names(), type).data(); }

}  // namespace tiltgate
