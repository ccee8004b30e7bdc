#include "console/config_endpoint.h"

#include <filesystem>
#include <fmt/format.h>

#include "config/config_loader.h"
#include "config/machine_checks.h"
#include "console/console_reply.h"
#include "store/whole_file_write.h"
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
  return json_reply(200, json{{"path", path_}, {"text", *text}, {"loaded_at", loaded_at}});
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

HttpReply ConfigEndpoint::apply(const ConfigText& text, std::string& audit_result) const {
  const auto failed = [&](unsigned status, std::string why) {
    audit_result = "error: " + why;
    return error_reply(status, std::move(why));
  };
  if (path_.empty()) return failed(404, "this gateway runs without a configuration file");
  auto loaded = checked_on_this_machine(load_config_string(text.text, path_, families_));
  if (!loaded) {
    audit_result = "refused: the configuration has errors";
    return json_reply(422, json{{"ok", false},
                                {"error", "the configuration has errors: nothing was changed"},
                                {"errors", errors_json(loaded.error())}});
  }
  auto old = toml_input::read_text_file(path_);
  if (!old) return failed(500, fmt::format("{}: {}", path_, old.error()));
  const std::string previous_path = path_ + ".previous";
  // Each keeps the owner, group and mode of the file it replaces (the configuration may hold
  // a broker's password); a first FILE.previous gets 0640.
  if (auto kept = write_whole_file(previous_path, *old, 0640, FileMode::keep_old); !kept)
    return failed(500, kept.error() + ": nothing was changed");
  if (auto written = write_whole_file(path_, text.text, 0640, FileMode::keep_old); !written)
    return failed(500, written.error() + ": nothing was changed");
  audit_result = "ok";
  return json_reply(200, json{{"ok", true}, {"previous", previous_path}});
}

}  // namespace tiltgate
