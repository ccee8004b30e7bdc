// The JSON bodies the web console's API takes (docs/web-console.md, "The API"), parsed from
// untrusted bytes: every field checked for its type and size, and what is wrong said in one
// line for the 400 reply. Pure; fuzzed (fuzz/).
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <string_view>

#include "driver/expected.h"

namespace tiltgate {

struct LoginRequest {
  std::string user;
  std::string password;
};
struct SettingRequest {
  std::string setting;
  double value = 0;
};
struct ConfigText {
  std::string text;
  // PUT /api/config's "confirm_s": how long the applied file waits for POST
  // /api/config/confirm before the previous one is restored
  // (docs/web-console.md, "Applying with a confirmation window").
  std::int64_t confirm_s = kDefaultConfirmSeconds;
  static constexpr std::int64_t kDefaultConfirmSeconds = 120;
  static constexpr std::int64_t kMinConfirmSeconds = 5, kMaxConfirmSeconds = 3600;
};
struct ScanRequest {
  std::int64_t from = 1, to = 0;  // to 0: the protocol's whole range
};
struct RawRequest {
  std::int64_t address = 0;
  std::int64_t function = 0;
  std::string data;  // hex bytes, e.g. "01 0A"; empty: none
};
// POST /api/config/form (docs/web-console.md, "Guided configuration").
struct FormEditRequest {
  std::string text;    // the configuration to change (the editor's text)
  std::string action;  // "add", "edit", "remove"
  std::string table;   // "bus", "sensor"
  std::string name;    // the table to edit or remove
  std::map<std::string, std::string> values;  // key -> as typed; "" leaves the key out
};

// The longest user name and password a login may carry: anything longer is refused before
// any hashing.
inline constexpr std::size_t kMaxUserName = 64;
inline constexpr std::size_t kMaxPassword = 1024;

Expected<LoginRequest, std::string> parse_login_request(std::string_view body);
Expected<SettingRequest, std::string> parse_setting_request(std::string_view body);
Expected<ConfigText, std::string> parse_config_text(std::string_view body);
Expected<ScanRequest, std::string> parse_scan_request(std::string_view body);
Expected<RawRequest, std::string> parse_raw_request(std::string_view body);
Expected<FormEditRequest, std::string> parse_form_edit_request(std::string_view body);

}  // namespace tiltgate
