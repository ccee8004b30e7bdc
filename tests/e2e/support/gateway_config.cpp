#include "e2e/support/gateway_config.h"

#include <fmt/format.h>

namespace tiltgate::test {

namespace {

// `extra_lines` as whole lines: a missing final newline is added, so tables concatenate.
std::string lines(std::string_view extra_lines) {
  std::string text(extra_lines);
  if (!text.empty() && text.back() != '\n') text += '\n';
  return text;
}

}  // namespace

std::string server_table(std::uint16_t port, std::string_view extra_lines) {
  return fmt::format("\n[server]\nlisten = \"127.0.0.1\"\nport = {}\n", port) + lines(extra_lines);
}

std::string http_table(std::uint16_t port, std::string_view extra_lines) {
  return fmt::format("\n[http]\nlisten = \"127.0.0.1\"\nport = {}\n", port) + lines(extra_lines);
}

std::string bus_table(std::string_view name, std::string_view tty, std::string_view extra_lines) {
  return fmt::format("\n[[bus]]\nname = \"{}\"\nport = \"{}\"\n", name, tty) + lines(extra_lines);
}

std::string sensor_table(std::string_view name, std::string_view bus, std::string_view model, int address,
                         int unit_id, std::string_view extra_lines) {
  return fmt::format("\n[[sensor]]\nname = \"{}\"\nbus = \"{}\"\nmodel = \"{}\"\naddress = {}\nunit_id = {}\n",
                     name, bus, model, address, unit_id) +
         lines(extra_lines);
}

}  // namespace tiltgate::test
