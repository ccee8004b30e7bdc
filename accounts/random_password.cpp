#include "accounts/random_password.h"

#include <sodium.h>

#include <string_view>

namespace tiltgate {

std::string random_password(std::size_t characters) {
  constexpr std::string_view kAlphabet = "abcdefghijkmnpqrstuvwxyzABCDEFGHJKLMNPQRSTUVWXYZ23456789";
  if (sodium_init() < 0) return {};
  std::string password;
  for (std::size_t i = 0; i < characters; ++i)
    password += kAlphabet[randombytes_uniform(std::uint32_t(kAlphabet.size()))];
  return password;
}

}  // namespace tiltgate
