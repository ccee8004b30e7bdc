// How the console's API answers: JSON bodies, and errors as {"error": "..."} that the page shows
// as they are.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "http/http_routes.h"

namespace tiltgate {

inline HttpReply json_reply(unsigned status, const nlohmann::json& body) {
  return HttpReply{status, "application/json",
                   body.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace)};
}

inline HttpReply error_reply(unsigned status, std::string message) {
  return json_reply(status, nlohmann::json{{"error", std::move(message)}});
}

}  // namespace tiltgate
