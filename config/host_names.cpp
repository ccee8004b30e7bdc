#include "config/host_names.h"

#include <arpa/inet.h>

#include <cctype>

namespace tiltgate::config {

bool is_ipv6_address(const std::string& text) {
  unsigned char buffer[sizeof(in6_addr)];
  return inet_pton(AF_INET6, text.c_str(), buffer) == 1;
}

bool is_ip_address(const std::string& text) {
  unsigned char buffer[sizeof(in_addr)];
  return inet_pton(AF_INET, text.c_str(), buffer) == 1 || is_ipv6_address(text);
}

// 1 to 63 characters a label, not starting or ending with '-', 253 characters at most.
bool is_host_name(std::string_view text) {
  if (text.empty() || text.size() > 253) return false;
  std::size_t label = 0;
  for (std::size_t i = 0; i <= text.size(); ++i) {
    if (i == text.size() || text[i] == '.') {
      if (label == 0 || label > 63 || text[i - 1] == '-' || text[i - label] == '-') return false;
      label = 0;
    } else if (std::isalnum(static_cast<unsigned char>(text[i])) || text[i] == '-') {
      ++label;
    } else {
      return false;
    }
  }
  return true;
}

}  // namespace tiltgate::config
