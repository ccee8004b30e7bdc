#include "console/pending_apply.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "store/whole_file_write.h"
#include "toml/text_file.h"

namespace tiltgate {

using json = nlohmann::json;

std::string previous_file(const std::string& config_path) { return config_path + ".previous"; }
std::string pending_file(const std::string& config_path) { return config_path + ".pending"; }

std::optional<PendingApply> read_pending(const std::string& config_path) {
  const std::string path = pending_file(config_path);
  auto text = toml_input::read_text_file(path);
  if (!text) {
    if (text.error().find(std::strerror(ENOENT)) != std::string::npos) return std::nullopt;
    return PendingApply{0, 0, "", fmt::format("(unreadable {}: {})", path, text.error())};
  }
  const json body = json::parse(*text, nullptr, false);
  PendingApply pending;
  if (!body.is_object() || !body.contains("deadline_unix_s") ||
      !body["deadline_unix_s"].is_number_integer()) {
    pending.changes = fmt::format("(unreadable {})", path);
    return pending;
  }
  pending.deadline_unix_s = body["deadline_unix_s"].get<std::int64_t>();
  pending.confirm_s = body.value("confirm_s", 0);
  pending.user = body.value("user", std::string());
  pending.changes = body.value("changes", std::string());
  return pending;
}

Expected<Done, std::string> write_pending(const std::string& config_path,
                                          const PendingApply& pending) {
  const json body{{"deadline_unix_s", pending.deadline_unix_s},
                  {"confirm_s", pending.confirm_s},
                  {"user", pending.user},
                  {"changes", pending.changes}};
  return write_whole_file(pending_file(config_path), body.dump() + "\n", 0640, FileMode::keep_old);
}

Expected<Done, std::string> remove_pending(const std::string& config_path) {
  const std::string path = pending_file(config_path);
  if (std::remove(path.c_str()) != 0 && errno != ENOENT)
    return Unexpected{fmt::format("{}: cannot remove: {}", path, std::strerror(errno))};
  return Done{};
}

Expected<Done, std::string> restore_previous(const std::string& config_path) {
  const std::string previous = previous_file(config_path);
  auto text = toml_input::read_text_file(previous);
  if (!text) return Unexpected{fmt::format("{}: {}", previous, text.error())};
  if (auto written = write_whole_file(config_path, *text, 0640, FileMode::keep_old); !written)
    return written;
  return remove_pending(config_path);
}

}  // namespace tiltgate
