// The web console's request bodies (console/console_requests.h): untrusted JSON from any client
// the [http] allow list admits, before any login. Each parser must answer a value or a reason,
// never crash, hang or read out of bounds.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "console/console_requests.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view body(reinterpret_cast<const char*>(data), size);
  (void)tiltgate::parse_login_request(body);
  (void)tiltgate::parse_setting_request(body);
  (void)tiltgate::parse_config_text(body);
  (void)tiltgate::parse_scan_request(body);
  (void)tiltgate::parse_raw_request(body);
  (void)tiltgate::parse_form_edit_request(body);
  return 0;
}
