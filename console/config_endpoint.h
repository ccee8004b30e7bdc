// The configuration through the console (admin): the served file as it is on disk, a check of
// an edited text with the loader and the machine's checks `tiltgate check` uses (errors at
// line:column), and apply: the text checked again, written atomically over the served file with
// the previous one kept as FILE.previous, then reloaded as a SIGHUP reloads it, under a
// confirmation window (console/confirm_window.h): unconfirmed, the previous file comes back. An
// invalid text changes nothing.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "config/config.h"
#include "console/confirm_window.h"
#include "console/console_requests.h"
#include "driver/family.h"
#include "http/http_routes.h"

namespace tiltgate {

// What the gateway serves as a request saw it, read on the buses' thread.
struct ServedConfig {
  const Config* config = nullptr;  // none: no gateway (a test's console)
  std::uint64_t loads = 0;         // Gateway::loads()
};

// What an apply did, for its audit record (console/apply_audit.h).
struct ApplyOutcome {
  std::string result;   // "ok: ...", "refused: ...", "error: ..."
  std::string changes;  // what it changes against the served configuration
};

class ConfigEndpoint {
 public:
  // `path`: the file the gateway serves (Config::path); empty: the gateway has none (the demo).
  // `window`: where an apply awaits its confirmation; none: applies are refused.
  ConfigEndpoint(std::string path, FamilyList families, ConfirmWindow* window)
      : path_(std::move(path)), families_(families), window_(window) {}

  HttpReply show(const std::string& loaded_at) const;   // GET /api/config
  HttpReply download() const;                           // GET /api/config.toml
  HttpReply check(const ConfigText& text) const;        // POST /api/config/check
  // PUT /api/config by `user`.
  HttpReply apply(const ConfigText& text, const std::string& user, const ServedConfig& served,
                  ApplyOutcome& outcome) const;
  // POST /api/config/confirm by `user`; `through_new_console`: the request came to a console
  // serving the [http] of the configuration the gateway serves now.
  HttpReply confirm(const std::string& user, const ServedConfig& served,
                    bool through_new_console) const;

  const std::string& path() const { return path_; }

 private:
  nlohmann::json pending_json() const;  // the open window, or null

  std::string path_;
  FamilyList families_;
  ConfirmWindow* window_;
};

}  // namespace tiltgate
