#include "device_server/serial_line_maker.h"

#include "device_server/network_port.h"
#include "device_server/port_url.h"

namespace tiltgate {

std::unique_ptr<SerialLine> make_serial_line(boost::asio::any_io_executor executor,
                                             SerialLineOptions options) {
  const Expected<PortAddress, std::string> address = parse_port(options.port);
  // The configuration refuses a bad URL at its line; one that slips through is opened as a
  // path, which fails and says so in the log.
  if (!address || !address->over_network()) {
    return std::make_unique<SerialLine>(executor, std::move(options));
  }
  NetworkPortOptions port{
      .name = options.name,
      .url = options.port,
      .address = *address,
      .setting = {.baud = options.baud,
                  .data_bits = 8,
                  .parity = idle_parity(options.framing),
                  .stop_bits = std::uint8_t(stop_bits_of(options.framing))},
      .reopen_min = options.reopen_min,
      .reopen_max = options.reopen_max,
      .connect_timeout = NetworkPortOptions{}.connect_timeout,
  };
  SerialLine::PortMaker make_port = [executor, port](std::function<void()> on_reopened) {
    return std::make_unique<NetworkPort>(executor, port, std::move(on_reopened));
  };
  return std::make_unique<SerialLine>(executor, std::move(options), make_port);
}

}  // namespace tiltgate
