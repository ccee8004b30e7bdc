// A Modbus TCP load generator for scripts/bench: N client connections on one epoll thread, each
// with one request outstanding (sent the moment the previous reply is in), function 03 or 04 of
// a fixed quantity, for a fixed time. Every reply is checked (transaction id, protocol id, MBAP
// length, unit id, function, byte count), so a server that answers wrongly, or not at all,
// cannot look fast: any bad reply, closed connection or request left unanswered at the end
// counts as an error and the exit status is 1.
//
// Prints one line: requests, errors, requests/s and the p50 / p99 / p99.9 latency (us) from the
// request's send to its reply's last byte, and the exception replies (with --count-exceptions,
// which counts them apart instead of failing on the first: requests/s and the latencies are the
// answered reads'). With --rate R each connection sends R requests a second, as a client with a
// scan time would, instead of the next one the moment a reply is in.
//
// Usage: bench_modbus_load --port N [--host 127.0.0.1] [--clients 1] [--function 4]
//                          [--address 0] [--quantity 10] [--unit 1] [--seconds 2]
//                          [--count-exceptions] [--rate R]
#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <sys/epoll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <string_view>
#include <vector>

namespace {

using Clock = std::chrono::steady_clock;

struct Options {
  std::string host = "127.0.0.1";
  int port = 0;
  int clients = 1;
  int function = 4;
  int address = 0;
  int quantity = 10;
  int unit = 1;
  double seconds = 2;
  // Exception replies are counted (and the client goes on) instead of failing the run.
  bool count_exceptions = false;
  // Requests a second per connection (0: each sent the moment the previous reply is in).
  double rate = 0;
};

struct Client {
  int fd = -1;
  std::uint16_t transaction = 0;
  Clock::time_point sent_at;
  std::array<std::uint8_t, 260> reply{};
  std::size_t received = 0;
  bool waiting = false;
  Clock::time_point due{};  // with --rate: when its next request is to be sent
};

[[noreturn]] void usage(const char* why) {
  std::fprintf(stderr,
               "%s\nusage: bench_modbus_load --port N [--host ADDR] [--clients N] "
               "[--function 3|4] [--address A] [--quantity Q] [--unit U] [--seconds S] "
               "[--count-exceptions] [--rate R]\n",
               why);
  std::exit(2);
}

Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string_view key = argv[i];
    if (key == "--count-exceptions") {
      o.count_exceptions = true;
      continue;
    }
    if (i + 1 >= argc) usage("every option takes a value");
    const char* value = argv[++i];
    if (key == "--host") o.host = value;
    else if (key == "--port") o.port = std::atoi(value);
    else if (key == "--clients") o.clients = std::atoi(value);
    else if (key == "--function") o.function = std::atoi(value);
    else if (key == "--address") o.address = std::atoi(value);
    else if (key == "--quantity") o.quantity = std::atoi(value);
    else if (key == "--unit") o.unit = std::atoi(value);
    else if (key == "--seconds") o.seconds = std::atof(value);
    else if (key == "--rate") o.rate = std::atof(value);
    else usage("unknown option");
  }
  if (o.port <= 0 || o.port > 65535) usage("--port is required");
  if (o.clients < 1 || (o.function != 3 && o.function != 4) || o.quantity < 1 ||
      o.quantity > 125 || o.seconds <= 0)
    usage("bad value");
  return o;
}

int connect_to(const Options& o) {
  const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_port = htons(std::uint16_t(o.port));
  if (fd < 0 || ::inet_pton(AF_INET, o.host.c_str(), &address.sin_addr) != 1 ||
      ::connect(fd, reinterpret_cast<sockaddr*>(&address), sizeof address) != 0) {
    std::fprintf(stderr, "connect to %s:%d: %s\n", o.host.c_str(), o.port, std::strerror(errno));
    std::exit(1);
  }
  const int one = 1;
  ::setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
  ::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL) | O_NONBLOCK);
  return fd;
}

class Load {
 public:
  explicit Load(const Options& o) : o_(o), clients_(std::size_t(o.clients)) {
    epoll_ = ::epoll_create1(EPOLL_CLOEXEC);
    for (std::size_t i = 0; i < clients_.size(); ++i) {
      clients_[i].fd = connect_to(o);
      clients_[i].transaction = std::uint16_t(i << 8);
      epoll_event event{};
      event.events = EPOLLIN;
      event.data.u64 = i;
      ::epoll_ctl(epoll_, EPOLL_CTL_ADD, clients_[i].fd, &event);
    }
    latencies_.reserve(1 << 20);
  }

  void run() {
    const Clock::time_point start = Clock::now();
    const Clock::time_point end =
        start + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(o_.seconds));
    for (Client& c : clients_) send_request(c);
    std::array<epoll_event, 256> events{};
    Clock::time_point now = start;
    while (now < end && errors_ == 0) {
      const int n = ::epoll_wait(epoll_, events.data(), int(events.size()), wait_ms(now));
      now = Clock::now();
      for (int i = 0; i < n; ++i) {
        Client& c = clients_[events[std::size_t(i)].data.u64];
        if (receive(c, now) && now < end && o_.rate <= 0) send_request(c);
      }
      if (o_.rate > 0 && now < end)
        for (Client& c : clients_)
          if (!c.waiting && c.fd >= 0 && now >= c.due) send_request(c);
    }
    elapsed_ = std::chrono::duration<double>(now - start).count();
    // Replies still due when time is up get up to a second, then count as errors.
    const Clock::time_point drain_until = Clock::now() + std::chrono::seconds(1);
    while (errors_ == 0 && outstanding() > 0 && Clock::now() < drain_until) {
      const int n = ::epoll_wait(epoll_, events.data(), int(events.size()), 100);
      for (int i = 0; i < n; ++i) receive(clients_[events[std::size_t(i)].data.u64], Clock::now(), false);
    }
    errors_ += outstanding();
  }

  void report() {
    std::sort(latencies_.begin(), latencies_.end());
    auto at = [&](double q) {
      if (latencies_.empty()) return 0.0;
      return latencies_[std::min(latencies_.size() - 1, std::size_t(q * double(latencies_.size())))] / 1000.0;
    };
    std::printf("requests=%zu errors=%zu req_per_s=%.0f p50_us=%.1f p99_us=%.1f p999_us=%.1f"
                " exceptions=%zu\n",
                latencies_.size(), errors_, double(latencies_.size()) / elapsed_, at(0.50),
                at(0.99), at(0.999), exceptions_);
  }

  std::size_t errors() const { return errors_; }

 private:
  std::size_t outstanding() const {
    return std::size_t(std::count_if(clients_.begin(), clients_.end(),
                                     [](const Client& c) { return c.waiting; }));
  }

  // How long epoll may sleep: 100 ms, or until the next paced request is due.
  int wait_ms(Clock::time_point now) const {
    if (o_.rate <= 0) return 100;
    Clock::time_point next = now + std::chrono::milliseconds(100);
    for (const Client& c : clients_)
      if (!c.waiting && c.fd >= 0) next = std::min(next, c.due);
    return int(std::max<long>(0, std::chrono::ceil<std::chrono::milliseconds>(next - now).count()));
  }

  void send_request(Client& c) {
    if (o_.rate > 0) {
      const auto period =
          std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(1.0 / o_.rate));
      c.due = std::max(c.due + period, Clock::now());
    }
    ++c.transaction;
    const std::uint8_t request[12] = {
        std::uint8_t(c.transaction >> 8), std::uint8_t(c.transaction), 0, 0, 0, 6,
        std::uint8_t(o_.unit), std::uint8_t(o_.function), std::uint8_t(o_.address >> 8),
        std::uint8_t(o_.address), std::uint8_t(o_.quantity >> 8), std::uint8_t(o_.quantity)};
    c.sent_at = Clock::now();
    c.received = 0;
    c.waiting = true;
    if (::send(c.fd, request, sizeof request, MSG_NOSIGNAL) != ssize_t(sizeof request)) fail(c, "send");
  }

  // Reads what arrived; true when a whole, correct reply is in.
  bool receive(Client& c, Clock::time_point now, bool count = true) {
    const std::size_t expected = 9 + 2 * std::size_t(o_.quantity);
    const ssize_t n = ::recv(c.fd, c.reply.data() + c.received, c.reply.size() - c.received, 0);
    if (n <= 0) {
      if (n < 0 && (errno == EAGAIN || errno == EINTR)) return false;
      fail(c, n == 0 ? "server closed the connection" : "recv");
      return false;
    }
    c.received += std::size_t(n);
    if (!c.waiting) return fail(c, "a reply nobody asked for");
    if (c.received < expected) {
      // An exception reply is 9 bytes: counted with --count-exceptions, else a failure.
      if (c.received >= 9 && (c.reply[7] & 0x80)) {
        if (!o_.count_exceptions || c.received != 9) return fail(c, "exception reply");
        c.waiting = false;
        if (count) ++exceptions_;
        return true;
      }
      return false;
    }
    const auto& r = c.reply;
    const std::uint16_t length = std::uint16_t(3 + 2 * o_.quantity);
    if (c.received != expected || r[0] != std::uint8_t(c.transaction >> 8) ||
        r[1] != std::uint8_t(c.transaction) || r[2] != 0 || r[3] != 0 || r[4] != (length >> 8) ||
        r[5] != (length & 0xFF) || r[6] != std::uint8_t(o_.unit) || r[7] != o_.function ||
        r[8] != 2 * o_.quantity)
      return fail(c, "wrong reply");
    c.waiting = false;
    if (count) latencies_.push_back(std::uint32_t(std::chrono::duration_cast<std::chrono::nanoseconds>(now - c.sent_at).count()));
    return true;
  }

  bool fail(Client& c, const char* why) {
    if (errors_ == 0) {
      std::fprintf(stderr, "transaction %u: %s (%zu bytes:", unsigned(c.transaction), why, c.received);
      for (std::size_t i = 0; i < std::min<std::size_t>(c.received, 12); ++i) std::fprintf(stderr, " %02X", c.reply[i]);
      std::fprintf(stderr, ")\n");
    }
    ++errors_;
    c.waiting = false;
    ::epoll_ctl(epoll_, EPOLL_CTL_DEL, c.fd, nullptr);
    c.fd = -1;
    return false;
  }

  Options o_;
  std::vector<Client> clients_;
  std::vector<std::uint32_t> latencies_;  // ns
  std::size_t errors_ = 0;
  std::size_t exceptions_ = 0;  // with --count-exceptions
  double elapsed_ = 0;
  int epoll_ = -1;
};

}  // namespace

int main(int argc, char** argv) {
  const Options options = parse(argc, argv);
  Load load(options);
  load.run();
  load.report();
  return load.errors() == 0 ? 0 : 1;
}
