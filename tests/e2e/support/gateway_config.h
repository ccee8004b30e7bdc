// The tables end-to-end tests put in a gateway config file, as TOML text to concatenate: each
// starts on a fresh line with its header and the keys every test gives it; `extra_lines` is
// appended as it stands (whole TOML lines, e.g. "writes = true\npoll_ms = 50"), so a test's
// config still shows every key it sets. The keys are those of docs/configuration.md.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

namespace tiltgate::test {

// [server] listening on 127.0.0.1:`port`.
std::string server_table(std::uint16_t port, std::string_view extra_lines = "");
// [http] (the status API) listening on 127.0.0.1:`port`.
std::string http_table(std::uint16_t port, std::string_view extra_lines = "");
// A [[bus]] named `name` on the serial device `tty`.
std::string bus_table(std::string_view name, std::string_view tty, std::string_view extra_lines = "");
// A [[sensor]] `name` of `model` at `address` on `bus`, served as Modbus unit `unit_id`.
std::string sensor_table(std::string_view name, std::string_view bus, std::string_view model, int address,
                         int unit_id, std::string_view extra_lines = "");

}  // namespace tiltgate::test
