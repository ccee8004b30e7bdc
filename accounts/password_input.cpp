#include "accounts/password_input.h"

#include <termios.h>
#include <unistd.h>

#include <iostream>
#include <optional>

namespace tiltgate {

namespace {

// Echo off on standard input for as long as it lives, then the terminal's settings back.
class EchoOff {
 public:
  EchoOff() {
    if (::tcgetattr(STDIN_FILENO, &saved_) != 0) return;
    termios quiet = saved_;
    quiet.c_lflag &= ~static_cast<tcflag_t>(ECHO);
    quiet.c_lflag |= ECHONL;  // the Enter still moves to the next line
    active_ = ::tcsetattr(STDIN_FILENO, TCSAFLUSH, &quiet) == 0;
  }
  ~EchoOff() {
    if (active_) ::tcsetattr(STDIN_FILENO, TCSAFLUSH, &saved_);
  }
  EchoOff(const EchoOff&) = delete;
  EchoOff& operator=(const EchoOff&) = delete;

 private:
  termios saved_{};
  bool active_ = false;
};

// One line of standard input without its end ("\n", or "\r\n" from a Windows editor).
std::optional<std::string> read_line() {
  std::string line;
  if (!std::getline(std::cin, line)) return std::nullopt;
  if (!line.empty() && line.back() == '\r') line.pop_back();
  return line;
}

// Echo off before the prompt shows: TCSAFLUSH drops what was typed before it, and a password
// typed once the prompt is there must find echo off already and be kept.
std::optional<std::string> prompt_without_echo(const std::string& prompt) {
  EchoOff echo_off;
  std::cerr << prompt << std::flush;
  return read_line();
}

}  // namespace

Expected<std::string, std::string> read_new_password(const std::string& name) {
  if (!::isatty(STDIN_FILENO)) {
    auto line = read_line();
    if (!line) return Unexpected(std::string("no password on standard input (one line)"));
    return std::move(*line);
  }
  auto first = prompt_without_echo("New password for " + name + ": ");
  if (!first) return Unexpected(std::string("no password typed"));
  auto second = prompt_without_echo("Again: ");
  if (!second) return Unexpected(std::string("no password typed"));
  if (*first != *second) return Unexpected(std::string("the two passwords typed differ"));
  return std::move(*first);
}

}  // namespace tiltgate
