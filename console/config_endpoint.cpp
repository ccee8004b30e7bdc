#include "console/config_endpoint.h"

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fmt/format.h>

#include "config/config_loader.h"
#include "config/reload_checks.h"
#include "config/machine_checks.h"
#include "console/console_reply.h"
#include "gateway/config_diff.h"
#include "toml/text_file.h"

namespace tiltgate {

namespace {

using json = nlohmann::json;

json errors_json(const ConfigErrors& errors) {
  json list = json::array();
  for (const ConfigError& error : errors)
    list.push_back({{"line", error.line},
                    {"column", error.column},
                    {"key", error.key},
                    {"message", error.message},
                    {"text", error.to_string()}});
  return list;
}

}  // namespace

HttpReply ConfigEndpoint::show(const std::string& loaded_at) const {
  if (path_.empty()) return error_reply(404, "this gateway runs without a configuration file");
  auto text = toml_input::read_text_file(path_);
  if (!text) return error_reply(500, fmt::format("{}: {}", path_, text.error()));
  return json_reply(200, json{{"path", path_},
                              {"text", *text},
                              {"loaded_at", loaded_at},
                              {"pending", pending_json()}});
}

json ConfigEndpoint::pending_json() const {
  const std::optional<PendingApply> pending = window_ ? window_->pending() : std::nullopt;
  if (!pending) return nullptr;
  const auto left = std::chrono::duration_cast<std::chrono::seconds>(
      pending->deadline() - std::chrono::system_clock::now());
  return json{{"user", pending->user},
              {"confirm_s", pending->confirm_s},
              {"deadline_unix_s", pending->deadline_unix_s},
              {"seconds_left", std::max<std::int64_t>(0, left.count())},
              {"changes", pending->changes}};
}

HttpReply ConfigEndpoint::download() const {
  if (path_.empty()) return error_reply(404, "this gateway runs without a configuration file");
  auto text = toml_input::read_text_file(path_);
  if (!text) return error_reply(500, fmt::format("{}: {}", path_, text.error()));
  HttpReply reply{200, "application/toml; charset=utf-8", std::move(*text)};
  reply.content_disposition = fmt::format(
      "attachment; filename=\"{}\"", std::filesystem::path(path_).filename().string());
  return reply;
}

HttpReply ConfigEndpoint::check(const ConfigText& text) const {
  // Checked as the served file: relative map files resolve against its folder.
  const std::string name = path_.empty() ? std::string("(console)") : path_;
  auto loaded = checked_on_this_machine(load_config_string(text.text, name, families_));
  if (!loaded) return json_reply(200, json{{"ok", false}, {"errors", errors_json(loaded.error())}});
  return json_reply(200, json{{"ok", true}, {"errors", json::array()}});
}

HttpReply ConfigEndpoint::apply(const ConfigText& text, const std::string& user,
                                const ServedConfig& served, ApplyOutcome& outcome) const {
  const auto failed = [&](unsigned status, std::string why) {
    outcome.result = "error: " + why;
    return error_reply(status, std::move(why));
  };
  if (path_.empty()) return failed(404, "this gateway runs without a configuration file");
  if (window_ == nullptr)
    return failed(503, "this gateway has no confirmation window to apply under");
  auto loaded = checked_on_this_machine(load_config_string(text.text, path_, families_));
  // A start-only table ([redundancy]) that the file changes is refused before it is written.
  if (loaded && served.config != nullptr)
    loaded = checked_for_reload(*served.config, std::move(loaded));
  if (!loaded) {
    outcome.result = "refused: the configuration has errors";
    return json_reply(422, json{{"ok", false},
                                {"error", "the configuration has errors: nothing was changed"},
                                {"errors", errors_json(loaded.error())}});
  }
  if (served.config != nullptr) outcome.changes = describe_changes(*served.config, *loaded);
  const auto now = std::chrono::system_clock::now().time_since_epoch();
  PendingApply pending;
  pending.confirm_s = int(text.confirm_s);
  pending.deadline_unix_s =
      std::chrono::duration_cast<std::chrono::seconds>(now).count() + text.confirm_s;
  pending.user = user;
  pending.changes = outcome.changes;
  if (auto written = window_->apply(text.text, pending, served.loads); !written)
    return failed(500, written.error() + ": nothing was changed");
  outcome.result = fmt::format("ok: awaits confirmation within {} s", text.confirm_s);
  // Where to confirm: the console as the applied file serves it.
  const HttpConfig& http = loaded->http;
  return json_reply(200, json{{"ok", true},
                              {"previous", previous_file(path_)},
                              {"confirm_s", pending.confirm_s},
                              {"deadline_unix_s", pending.deadline_unix_s},
                              {"changes", outcome.changes},
                              {"console", json{{"enabled", http.enabled},
                                               {"listen", http.listen},
                                               {"port", http.port},
                                               {"https", http.https()}}}});
}

HttpReply ConfigEndpoint::confirm(const std::string& user, const ServedConfig& served,
                                  bool through_new_console) const {
  if (window_ == nullptr || !window_->pending())
    return error_reply(409, "no applied configuration awaits confirmation");
  if (!through_new_console)
    return error_reply(409, "confirm through the console the applied configuration serves "
                            "([http] listen and port as applied)");
  auto confirmed = window_->confirm(user, served.loads);
  if (!confirmed) return error_reply(409, confirmed.error());
  return json_reply(200, json{{"ok", true},
                              {"applied_by", confirmed->user},
                              {"changes", confirmed->changes}});
}

}  // namespace tiltgate
