// A pseudo-terminal pair: the simulator (or a test) holds the master side, and the gateway
// opens the slave path as if it were /dev/ttyUSB0. Used by tests, the demo and `tiltgate sim`.
#pragma once

#include <string>

#include "driver/expected.h"

namespace tiltgate {

class PseudoTerminal {
 public:
  // Opens a new pair in raw mode (no echo, no line editing, 8N1).
  static Expected<PseudoTerminal, std::string> open();

  PseudoTerminal(PseudoTerminal&& other) noexcept;
  PseudoTerminal& operator=(PseudoTerminal&& other) noexcept;
  PseudoTerminal(const PseudoTerminal&) = delete;
  PseudoTerminal& operator=(const PseudoTerminal&) = delete;
  ~PseudoTerminal();

  int master_fd() const { return master_fd_; }
  // Gives up ownership of the master descriptor (to an asio stream_descriptor, say).
  int release_master();
  // The slave side the pair holds open (closed with it).
  int slave_fd() const { return slave_fd_; }
  const std::string& slave_path() const { return slave_path_; }
  // Closes both sides: to the process on the slave side it looks like an unplugged adapter.
  void close();

 private:
  PseudoTerminal(int master_fd, int slave_fd, std::string slave_path);

  int master_fd_ = -1;
  // Held open so the slave's termios settings persist and the master does not read EIO while
  // the gateway has the slave closed (between reopen attempts).
  int slave_fd_ = -1;
  std::string slave_path_;
};

}  // namespace tiltgate
