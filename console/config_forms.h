// The console's guided configuration (docs/web-console.md, "Guided configuration"): forms to
// add, change and remove a [[bus]] or a [[sensor]], beside the text editor. Each key is shown as
// the configuration reference describes it (config/key_reference.h); a text's tables are read as
// typed (config/form_values.h); a filled form becomes the text with that table added, changed or
// removed line by line (config/config_edit.h), checked as `tiltgate check` checks it, each error
// at its field when it is the form's table's. Nothing is applied here: the page puts the text in
// the editor, whose apply keeps its diff and confirmation.
#pragma once

#include <string>

#include "console/console_requests.h"
#include "driver/family.h"
#include "http/http_routes.h"

namespace tiltgate {

class ConfigForms {
 public:
  // `path`: the served file, so relative map and profile paths resolve as they will when applied.
  ConfigForms(std::string path, FamilyList families)
      : path_(std::move(path)), families_(families) {}

  HttpReply keys() const;                              // GET /api/config/form
  HttpReply tables(const ConfigText& text) const;      // POST /api/config/tables
  HttpReply edit(const FormEditRequest& request) const;  // POST /api/config/form

 private:
  std::string path_;
  FamilyList families_;
};

}  // namespace tiltgate
