// A password the gateway makes itself, for accounts that live as long as one run (the demo's,
// docs/web-console.md, "Try it"): libsodium's generator over an alphabet without look-alikes
// (no 0/O, 1/l/I), so it can be read off a terminal and typed.
#pragma once

#include <cstddef>
#include <string>

namespace tiltgate {

// `characters` long; empty when libsodium cannot start.
std::string random_password(std::size_t characters = 16);

}  // namespace tiltgate
