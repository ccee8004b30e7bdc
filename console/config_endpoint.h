// The configuration through the console (admin): the served file as it is on disk, a check of
// an edited text with the loader `tiltgate check` uses (errors at line:column), and apply: the
// text checked again, written atomically beside the served file with the previous one kept as
// FILE.previous, then reloaded as a SIGHUP reloads it. An invalid text changes nothing.
#pragma once

#include <string>

#include "console/console_requests.h"
#include "driver/family.h"
#include "status/http_routes.h"

namespace tiltgate {

class ConfigEndpoint {
 public:
  // `path`: the file the gateway serves (Config::path); empty: the gateway has none (the demo).
  ConfigEndpoint(std::string path, FamilyList families) : path_(std::move(path)), families_(families) {}

  HttpReply show(const std::string& loaded_at) const;   // GET /api/config
  HttpReply download() const;                           // GET /api/config.toml
  HttpReply check(const ConfigText& text) const;        // POST /api/config/check
  // PUT /api/config; `audit_result` says what came of it in the audit trail's words ("ok",
  // "refused: ...", "error: ...").
  HttpReply apply(const ConfigText& text, std::string& audit_result) const;

  const std::string& path() const { return path_; }

 private:
  std::string path_;
  FamilyList families_;
};

}  // namespace tiltgate
