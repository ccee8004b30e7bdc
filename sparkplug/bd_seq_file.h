// The bdSeq of the edge node's last CONNECT, kept in state_dir across restarts (Sparkplug
// 3.0.0, tck-id-topics-nbirth-bdseq-increment: the next CONNECT's is one more). A small text
// file ("17\n") replaced atomically before each CONNECT (written aside, synced, renamed), so a
// crash leaves the old value or the new one, never a torn one.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>

#include "driver/expected.h"

namespace tiltgate::sparkplug {

// The stored bdSeq; none when the file does not exist (the first start). An error when it
// cannot be read or does not hold a number 0..255.
Expected<std::optional<std::uint8_t>, std::string> read_bd_seq(const std::filesystem::path& file);
Expected<Done, std::string> write_bd_seq(const std::filesystem::path& file, std::uint8_t bd_seq);

}  // namespace tiltgate::sparkplug
