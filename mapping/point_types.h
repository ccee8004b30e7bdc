// The vocabulary of a register-map point: tables, data types, register and byte order, angle
// units, rounding, and what an offline sensor's measurements read as. Plain enums with the
// names a map file uses, so config/ can parse them without knowing how they are encoded.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string_view>

#include "driver/setting_role.h"

namespace tiltgate {

enum class RegisterTable : std::uint8_t { coil, discrete, input, holding };

enum class PointType : std::uint8_t {
  boolean,
  uint16,
  int16,
  uint32,
  int32,
  float32,
  float64,
  string,
};

// [server] word_order: the default layout of multi-register values.
enum class WordOrder { big, little };  // 32-bit values: high word first, or low word first

// How the bytes of a multi-byte value sit in the registers, named after a 32-bit value whose
// bytes are A B C D, most significant first: ABCD is plain big-endian (Modbus' own order),
// CDAB swaps the words, BADC swaps the bytes within each word, DCBA does both. For 64-bit
// values the same two choices give ABCDEFGH, GHEFCDAB, BADCFEHG and HGFEDCBA; for 16-bit
// values only the byte swap counts (AB or BA).
enum class RegisterOrder : std::uint8_t { abcd, cdab, badc, dcba };

RegisterOrder register_order(WordOrder server);  // big: ABCD, little: CDAB
bool swaps_words(RegisterOrder order);
bool swaps_bytes(RegisterOrder order);

// What an angle point shows. Percent grade is 100 * tan(angle): unbounded near +-90 degrees.
enum class AngleUnit : std::uint8_t { degrees, milliradians, percent_grade };

// How a scaled value becomes an integer register. Every mode then saturates at the type's
// limits instead of wrapping.
enum class Rounding : std::uint8_t { nearest, floor, ceil, truncate };

// What a read of a measurement returns while the sensor is offline or its reading is stale.
enum class OfflineRead { exception, last_value, substitute };

// A name as a map file writes it, and the value it stands for.
template <class E>
struct Named {
  std::string_view name;
  E value;
};

std::span<const Named<RegisterTable>> table_names();   // coil, discrete, input, holding
std::span<const Named<PointType>> type_names();        // bool, uint16, ..., string
std::span<const Named<RegisterOrder>> order_names();   // ABCD, CDAB, BADC, DCBA
std::span<const Named<AngleUnit>> angle_unit_names();  // deg, mrad, percent
std::span<const Named<Rounding>> rounding_names();     // nearest, floor, ceil, truncate
std::span<const Named<SettingRole>> role_names();     // operator, admin

template <class E>
std::optional<E> from_name(std::span<const Named<E>> names, std::string_view name) {
  for (const Named<E>& n : names)
    if (n.name == name) return n.value;
  return std::nullopt;
}

template <class E>
std::string_view name_of(std::span<const Named<E>> names, E value) {
  for (const Named<E>& n : names)
    if (n.value == value) return n.name;
  return "?";
}

const char* to_string(RegisterTable table);
const char* to_string(PointType type);

}  // namespace tiltgate
