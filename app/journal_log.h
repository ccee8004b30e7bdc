// Log lines for the systemd journal: when stderr is the journal's stream (JOURNAL_STREAM, see
// systemd.exec(5)), each line starts with its syslog priority, "<4>" for a warning, which
// journald takes as the entry's PRIORITY (sd-daemon.h's SD_WARNING and friends), so
// `journalctl -p warning` finds them; and no timestamp, as the journal keeps its own.
#pragma once

#include <memory>
#include <spdlog/common.h>
#include <spdlog/formatter.h>
#include <string_view>
#include <sys/types.h>

namespace tiltgate {

// syslog(3) priority of an spdlog level: critical 2 (crit), error 3, warn 4, info 6 (info),
// debug and trace 7 (debug).
int syslog_priority(spdlog::level::level_enum level);

// Whether JOURNAL_STREAM's value ("DEVICE:INODE", both decimal) names this file.
bool journal_stream_is(std::string_view journal_stream, dev_t device, ino_t inode);

// Whether stderr is the stream systemd connected to the journal (not merely inherited by a
// child whose stderr was redirected elsewhere).
bool stderr_is_journal();

// The formatter for the journal: "<PRIORITY>message".
std::unique_ptr<spdlog::formatter> journal_formatter();

}  // namespace tiltgate
