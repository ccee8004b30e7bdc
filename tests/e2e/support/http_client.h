// A minimal HTTP/1.1 client over loopback sockets for the status API's end-to-end tests: a
// request with Connection: close, read until the server closes, and the reply parsed.
#pragma once

#include <arpa/inet.h>
#include <doctest/doctest.h>
#include <fmt/format.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <sys/time.h>
#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <cstdint>
#include <map>
#include <sstream>
#include <string>

namespace tiltgate::test {

// A connected loopback socket whose reads give up after `seconds` (so a test cannot hang).
inline int connect_to(std::uint16_t port, int seconds = 30) {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  REQUIRE(fd >= 0);
  timeval limit{seconds, 0};
  ::setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &limit, sizeof limit);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_port = htons(port);
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  REQUIRE(::connect(fd, reinterpret_cast<sockaddr*>(&address), sizeof address) == 0);
  return fd;
}

inline void send_all(int fd, const std::string& bytes) {
  REQUIRE(::send(fd, bytes.data(), bytes.size(), MSG_NOSIGNAL) == ssize_t(bytes.size()));
}

// Everything until the server closes; `timed_out` when it did not close in time.
inline std::string read_to_close(int fd, bool* timed_out = nullptr) {
  std::string bytes;
  char buffer[4096];
  for (;;) {
    const ssize_t n = ::recv(fd, buffer, sizeof buffer, 0);
    if (n > 0) {
      bytes.append(buffer, std::size_t(n));
      continue;
    }
    if (timed_out) *timed_out = n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK);
    return bytes;
  }
}

struct Response {
  int status = 0;
  std::map<std::string, std::string> headers;  // names lower-cased
  std::string body;
};

inline Response parse_response(const std::string& raw) {
  Response r;
  const auto end = raw.find("\r\n\r\n");
  REQUIRE_MESSAGE(end != std::string::npos, raw);
  std::istringstream head(raw.substr(0, end));
  std::string line;
  std::getline(head, line);
  REQUIRE_MESSAGE(line.starts_with("HTTP/1.1 "), line);
  r.status = std::stoi(line.substr(9, 3));
  while (std::getline(head, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const auto colon = line.find(':');
    REQUIRE(colon != std::string::npos);
    std::string name = line.substr(0, colon);
    for (char& c : name) c = char(std::tolower(static_cast<unsigned char>(c)));
    r.headers[name] = line.substr(line.find_first_not_of(' ', colon + 1));
  }
  r.body = raw.substr(end + 4);
  if (r.headers.count("content-length"))
    CHECK(r.body.size() == std::stoul(r.headers["content-length"]));
  return r;
}

inline Response request(std::uint16_t port, const std::string& method,
                        const std::string& target) {
  const int fd = connect_to(port);
  send_all(fd, fmt::format("{} {} HTTP/1.1\r\nHost: localhost\r\nConnection: close\r\n\r\n",
                           method, target));
  bool timed_out = false;
  const std::string raw = read_to_close(fd, &timed_out);
  ::close(fd);
  REQUIRE_FALSE(timed_out);
  return parse_response(raw);
}

inline Response get(std::uint16_t port, const std::string& target) {
  return request(port, "GET", target);
}

}  // namespace tiltgate::test
