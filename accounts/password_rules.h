// What a new console password must be (docs/web-console.md, "Password rules"): at least
// kMinPasswordCharacters characters, not the account's name and not one of the most common
// passwords, since an account is guessed at up to 10 times a minute from the network
// (console/login_throttle.h) and a password from a guessing list falls within its first tries.
// `tiltgate user add|passwd --allow-weak` skips these checks, for test rigs. Pure.
#pragma once

#include <optional>
#include <string>
#include <string_view>

namespace tiltgate {

inline constexpr std::size_t kMinPasswordCharacters = 10;

// Why `password` is too weak for the account `name`; none when it may be used.
std::optional<std::string> password_weakness(std::string_view name, std::string_view password);

}  // namespace tiltgate
