#include "serial/pseudo_terminal.h"

#include <fcntl.h>
#include <pty.h>
#include <termios.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <utility>

namespace tiltgate {

Expected<PseudoTerminal, std::string> PseudoTerminal::open() {
  int master = -1;
  int slave = -1;
  char name[128] = {};
  termios raw{};
  cfmakeraw(&raw);
  raw.c_cflag |= CLOCAL | CREAD;
  if (::openpty(&master, &slave, name, &raw, nullptr) != 0) {
    return Unexpected(std::string("openpty: ") + std::strerror(errno));
  }
  ::fcntl(master, F_SETFD, FD_CLOEXEC);
  ::fcntl(slave, F_SETFD, FD_CLOEXEC);
  return PseudoTerminal(master, slave, name);
}

PseudoTerminal::PseudoTerminal(int master_fd, int slave_fd, std::string slave_path)
    : master_fd_(master_fd), slave_fd_(slave_fd), slave_path_(std::move(slave_path)) {}

PseudoTerminal::PseudoTerminal(PseudoTerminal&& other) noexcept
    : master_fd_(std::exchange(other.master_fd_, -1)),
      slave_fd_(std::exchange(other.slave_fd_, -1)),
      slave_path_(std::move(other.slave_path_)) {}

PseudoTerminal& PseudoTerminal::operator=(PseudoTerminal&& other) noexcept {
  if (this != &other) {
    close();
    master_fd_ = std::exchange(other.master_fd_, -1);
    slave_fd_ = std::exchange(other.slave_fd_, -1);
    slave_path_ = std::move(other.slave_path_);
  }
  return *this;
}

PseudoTerminal::~PseudoTerminal() { close(); }

int PseudoTerminal::release_master() { return std::exchange(master_fd_, -1); }

void PseudoTerminal::close() {
  if (master_fd_ >= 0) ::close(std::exchange(master_fd_, -1));
  if (slave_fd_ >= 0) ::close(std::exchange(slave_fd_, -1));
}

}  // namespace tiltgate
