// What a valid configuration needs of the machine that runs it, checked before it is served
// (`tiltgate check`, `run`, a reload and the console's check and apply), so a file that passes
// the check cannot fail at the next start or lock the console out
// (docs/configuration.md, "What check asks of the machine"): the [server] user exists, each
// listen address is one this machine has, and each TLS certificate file holds a certificate,
// its key file the matching key. Apart from the loader, which stays a pure function of the text (fuzzed, unit-tested
// anywhere). Errors name the key and the file, never a file's contents.
#pragma once

#include "config/config.h"
#include "config/config_loader.h"

namespace tiltgate {

ConfigErrors check_on_this_machine(const Config& config);

// `loaded` with check_on_this_machine's errors, when it loaded.
Expected<Config, ConfigErrors> checked_on_this_machine(Expected<Config, ConfigErrors> loaded);

}  // namespace tiltgate
