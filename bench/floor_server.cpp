/* The least a Modbus TCP server can spend on a read on this machine, for scripts/bench to show
 * how close the gateway and the reference come to it (docs/performance.md, "Where the time
 * goes"): one thread, one epoll set, and per read one epoll_wait, one recv and one send. It
 * answers functions 03 and 04 with registers that hold their address and checks nothing else:
 * no map, no cache, no deadlines, no admission. Not a server to use.
 *
 * A socket is read until a read comes back short (the queue is then empty, and edge-triggered
 * epoll reports the next byte that arrives), and every whole request read is answered with one
 * send.
 *
 * Usage: bench_floor_server PORT   (listens on 127.0.0.1 only; SIGTERM or SIGINT ends it) */
#include <arpa/inet.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <signal.h>
#include <sys/epoll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>

namespace {

volatile sig_atomic_t stopping = 0;

void stop(int) { stopping = 1; }

struct Client {
  int fd = -1;
  std::uint8_t in[4096];
  std::size_t have = 0;
  std::uint8_t out[16 * 260];
};

// Every whole request in `c.in`, answered into `c.out`; the bytes of replies made.
std::size_t answer(Client& c) {
  std::size_t at = 0, made = 0;
  while (c.have - at >= 7) {
    const std::uint8_t* q = c.in + at;
    const std::size_t size = 6 + std::size_t((q[4] << 8) | q[5]);
    if (c.have - at < size || made + 260 > sizeof c.out) break;
    const unsigned count = size >= 12 ? unsigned((q[10] << 8) | q[11]) % 126 : 0;
    std::uint8_t* r = c.out + made;
    std::memcpy(r, q, 8);  // transaction, protocol, unit, function
    r[4] = 0;
    r[5] = std::uint8_t(3 + 2 * count);
    r[8] = std::uint8_t(2 * count);
    const unsigned first = unsigned((q[8] << 8) | q[9]);
    for (unsigned i = 0; i < count; ++i) {
      r[9 + 2 * i] = std::uint8_t((first + i) >> 8);
      r[10 + 2 * i] = std::uint8_t(first + i);
    }
    made += 9 + 2 * count;
    at += size;
  }
  std::memmove(c.in, c.in + at, c.have - at);
  c.have -= at;
  return made;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s PORT\n", argv[0]);
    return 2;
  }
  const int listener = ::socket(AF_INET, SOCK_STREAM | SOCK_NONBLOCK, 0);
  const int one = 1;
  ::setsockopt(listener, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_port = htons(std::uint16_t(std::atoi(argv[1])));
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (::bind(listener, reinterpret_cast<sockaddr*>(&address), sizeof address) != 0 ||
      ::listen(listener, 1024) != 0) {
    std::perror("listen");
    return 1;
  }
  struct sigaction action {};
  action.sa_handler = stop;
  sigaction(SIGTERM, &action, nullptr);
  sigaction(SIGINT, &action, nullptr);
  const int epoll = ::epoll_create1(0);
  epoll_event event{};
  event.events = EPOLLIN;
  event.data.ptr = nullptr;
  ::epoll_ctl(epoll, EPOLL_CTL_ADD, listener, &event);
  epoll_event ready[128];
  while (!stopping) {
    const int n = ::epoll_wait(epoll, ready, 128, -1);
    for (int i = 0; i < n; ++i) {
      auto* c = static_cast<Client*>(ready[i].data.ptr);
      if (c == nullptr) {  // the listener
        const int fd = ::accept4(listener, nullptr, nullptr, SOCK_NONBLOCK);
        if (fd < 0) continue;
        ::setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
        c = new Client;
        c->fd = fd;
        epoll_event watched{};
        watched.events = EPOLLIN | EPOLLET;
        watched.data.ptr = c;
        ::epoll_ctl(epoll, EPOLL_CTL_ADD, fd, &watched);
        continue;
      }
      for (;;) {
        const std::size_t room = sizeof c->in - c->have;
        const ssize_t got = ::recv(c->fd, c->in + c->have, room, 0);
        if (got <= 0) {
          if (got == 0) {  // closed: its events end with its descriptor
            ::close(c->fd);
            delete c;
          }
          break;
        }
        c->have += std::size_t(got);
        if (const std::size_t made = answer(*c)) ::send(c->fd, c->out, made, MSG_NOSIGNAL);
        if (std::size_t(got) < room) break;
      }
    }
  }
  return 0;
}
