// The line for a bus's port, whatever it names: a local tty, or a serial device server's port
// (tcp:// or rfc2217://, device_server/port_url.h). The gateway and the commissioning commands
// make every line here, so a URL works wherever a tty path does.
#pragma once

#include <boost/asio/any_io_executor.hpp>
#include <memory>

#include "serial/serial_line.h"

namespace tiltgate {

std::unique_ptr<SerialLine> make_serial_line(boost::asio::any_io_executor executor,
                                             SerialLineOptions options);

}  // namespace tiltgate
