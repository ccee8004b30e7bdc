#include "accounts/password_rules.h"

#include <algorithm>
#include <cctype>
#include <fmt/format.h>

namespace tiltgate {

namespace {

// The passwords of 10 characters or more that lead the public lists of leaked passwords
// (SecLists' most common, NCSC's 100,000), with the obvious ones for a gateway. A short list:
// its job is to stop the first guesses of any guessing tool, not to judge a password.
constexpr std::string_view kCommonPasswords[] = {
    "0000000000",   "0123456789",    "1111111111",   "1234567890",   "123456789a",
    "1234567890a",  "12345678910",   "123123123123", "1q2w3e4r5t",   "1qaz2wsx3edc",
    "a123456789",   "abc1234567",    "abcdefghij",   "administrator", "admin12345",
    "adminadmin",   "changeme123",   "iloveyou12",   "letmein123",   "passw0rd12",
    "password1!",   "password12",    "password123",  "password1234", "qazwsxedc123",
    "qwerty1234",   "qwerty12345",   "qwerty123456", "qwertyuiop",   "qwertyuiop1",
    "tiltgate123",  "welcome123",    "zaq12wsxcde",  "1q2w3e4r5t6y", "9876543210",
};

std::string lower(std::string_view text) {
  std::string out(text);
  std::transform(out.begin(), out.end(), out.begin(),
                 [](unsigned char c) { return char(std::tolower(c)); });
  return out;
}

// Characters, not bytes: a UTF-8 sequence counts once (its continuation bytes are 10xxxxxx).
std::size_t characters(std::string_view text) {
  return std::size_t(std::count_if(text.begin(), text.end(), [](char c) {
    return (static_cast<unsigned char>(c) & 0xC0) != 0x80;
  }));
}

}  // namespace

std::optional<std::string> password_weakness(std::string_view name, std::string_view password) {
  if (characters(password) < kMinPasswordCharacters)
    return fmt::format("a password needs at least {} characters", kMinPasswordCharacters);
  const std::string lowered = lower(password);
  if (lowered == lower(name)) return std::string("the password is the account's name");
  if (std::find(std::begin(kCommonPasswords), std::end(kCommonPasswords), lowered) !=
      std::end(kCommonPasswords))
    return std::string("the password is one of the most common ones");
  return std::nullopt;
}

}  // namespace tiltgate
