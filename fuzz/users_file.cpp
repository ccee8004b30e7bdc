// The web console's users file (accounts/users_file.h): a file an admin edits by hand too, read
// again whenever it changes. Any text must give accounts or errors at their lines, never a crash
// or a hang (nothing here hashes: parsing checks a hash's form, not a password).
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "accounts/users_file.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  (void)tiltgate::UsersFile::parse(text, "users");
  return 0;
}
