// What a reload (SIGHUP, `systemctl reload`, the console's apply) may not change: the tables the
// gateway reads only at start. A reload that changes one is refused with what changed and that
// a restart applies it, rather than applied in part: a [redundancy] role changed in the file
// but not in the running process would otherwise take effect unannounced at some later restart
// (a power cut), possibly as a second primary on the lines (docs/configuration.md,
// "[redundancy]"). Pure: the caller has the running configuration.
#pragma once

#include "config/config.h"
#include "config/config_loader.h"

namespace tiltgate {

// One error for each start-only table that `loaded` changes from `running` (key "redundancy"),
// without a line, as check_on_this_machine's; none when the reload may go ahead.
ConfigErrors check_reload(const Config& running, const Config& loaded);

// `loaded` with check_reload's errors, when it loaded.
Expected<Config, ConfigErrors> checked_for_reload(const Config& running,
                                                  Expected<Config, ConfigErrors> loaded);

}  // namespace tiltgate
