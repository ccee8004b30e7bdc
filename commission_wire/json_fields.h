// Reading a peer's JSON object strictly, field by field, for the engine's events and a command's
// request as the control socket carries them (commission_wire/event_json.h,
// commission_wire/command_request.h): every field present and of its type, every integer within its
// C++ type's range (nlohmann's get<> would wrap -1 into 4294967295 or cut 1.5 to 1). A field
// that fails throws JsonFieldError naming it by its path ("found[2].baud"); only the public
// readers catch it, so nothing is thrown past them. Fields the reader does not know are
// ignored. Optionals are null when empty, both ways.
#pragma once

#include <cstdint>
#include <functional>
#include <limits>
#include <nlohmann/json.hpp>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace tiltgate {

struct JsonFieldError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// An optional as a value or null.
template <class T>
nlohmann::json json_or_null(const std::optional<T>& value) {
  return value ? nlohmann::json(*value) : nlohmann::json(nullptr);
}

// One JSON object and where it sits in the whole ("" at the top, "sensor", "found[2]").
class JsonObjectReader {
 public:
  // Throws unless `object` is a JSON object.
  JsonObjectReader(const nlohmann::json& object, std::string path);

  bool boolean(std::string_view key) const;
  std::string string(std::string_view key) const;
  double number(std::string_view key) const;  // an integer is a number too
  template <class T>
  T integer(std::string_view key) const {
    return checked_integer<T>(field(key), key);
  }
  std::vector<std::uint8_t> hex_bytes(std::string_view key) const;  // "01 03 0A", driver/hex.h

  // Null: none.
  std::optional<double> optional_number(std::string_view key) const;
  template <class T>
  std::optional<T> optional_integer(std::string_view key) const {
    const nlohmann::json& value = field(key);
    if (value.is_null()) return std::nullopt;
    return checked_integer<T>(value, key);
  }

  JsonObjectReader object(std::string_view key) const;
  std::vector<std::string> string_list(std::string_view key) const;
  template <class T>
  std::vector<T> integer_list(std::string_view key) const {
    std::vector<T> list;
    const nlohmann::json& array = array_field(key);
    for (std::size_t i = 0; i < array.size(); ++i)
      list.push_back(checked_integer<T>(array[i], item_name(key, i)));
    return list;
  }
  // Each item an object, read by `read_item`.
  template <class T>
  std::vector<T> object_list(std::string_view key,
                             const std::function<T(const JsonObjectReader&)>& read_item) const {
    std::vector<T> list;
    const nlohmann::json& array = array_field(key);
    for (std::size_t i = 0; i < array.size(); ++i)
      list.push_back(read_item(JsonObjectReader(array[i], path_of(item_name(key, i)))));
    return list;
  }

  // Whether the object has the field at all (a request's optional sections).
  bool has(std::string_view key) const;
  // The field's path from the top, for a message of the caller's own ("found[2].baud").
  std::string path_of(std::string_view key) const;

 private:
  const nlohmann::json& field(std::string_view key) const;
  const nlohmann::json& array_field(std::string_view key) const;
  static std::string item_name(std::string_view key, std::size_t index);
  [[noreturn]] void fail(std::string_view key, std::string_view expected,
                         const nlohmann::json& value) const;

  template <class T>
  T checked_integer(const nlohmann::json& value, std::string_view key) const {
    if (value.is_number_unsigned()) {
      const auto n = value.get<std::uint64_t>();
      if (std::in_range<T>(n)) return static_cast<T>(n);
    } else if (value.is_number_integer()) {
      const auto n = value.get<std::int64_t>();
      if (std::in_range<T>(n)) return static_cast<T>(n);
    }
    fail(key, integer_expectation(std::numeric_limits<T>::min(), std::numeric_limits<T>::max()),
         value);
  }
  static std::string integer_expectation(std::intmax_t min, std::uintmax_t max);

  const nlohmann::json& object_;
  std::string path_;
};

}  // namespace tiltgate
