// The configuration loader (config/): any text, with the families this build registers, must
// give a Config or a list of errors, never a crash. Errors must name something: a syntax error
// its position, any other its key or its message.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "config/config_loader.h"
#include "fuzz/chunks.h"

using tiltgate::fuzz::check;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::string_view text(reinterpret_cast<const char*>(data), size);
  auto loaded = tiltgate::load_config_string(text, "fuzz.toml", tiltgate::registered_families());
  if (!loaded) {
    check(!loaded.error().empty());
    for (const auto& error : loaded.error()) check(!error.to_string().empty());
  }
  return 0;
}
