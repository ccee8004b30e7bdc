#include "audit/audit_counts.h"

namespace tiltgate {

std::string_view audit_result_class(std::string_view result) {
  for (std::string_view name : {"ack", "nak", "timeout", "refused", "error", "ok"})
    if (result.starts_with(name) &&
        (result.size() == name.size() || result[name.size()] == ' ' ||
         result[name.size()] == ':'))
      return name;
  return "error";
}

}  // namespace tiltgate
