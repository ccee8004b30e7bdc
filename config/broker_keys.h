// The keys [mqtt] and [sparkplug] share: both reach an MQTT broker with libmosquitto, with the
// same credentials and TLS files (docs/configuration.md, "[mqtt]" and "[sparkplug]"), so both
// read and check them here, with the same messages.
#pragma once

#include <string>
#include <string_view>

#include "toml/toml_reader.h"

namespace tiltgate::config {

// The machine's host name, for the default client ids, topic prefix and edge node id;
// "localhost" when it has none.
std::string host_name();

struct BrokerKeys {
  std::string host;
  std::uint16_t port = 1883;
  int keepalive_s = 30;
  std::string username, password;
  std::string ca_file, cert_file, key_file;
};

// host (required when `host_required`), port, keepalive_s, username/password and the TLS
// files into `out`, which holds the defaults; each mistake reported at its key.
void read_broker_keys(toml_input::TableReader& in, bool host_required, BrokerKeys& out);

}  // namespace tiltgate::config
