// The gateway's relay framer (control/control_relay.h) on a socket pair, the command's end
// played by a thread of the test's own: the relay asks asynchronously, so the event loop it
// runs on (the buses' thread in the gateway) goes on while a command thinks, also when it
// never answers; its reset is sent without waiting; a command that is gone, too slow or says
// something else breaks the relay.
#include <doctest/doctest.h>

#include <boost/asio/co_spawn.hpp>
#include <boost/asio/detached.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/local/connect_pair.hpp>
#include <boost/asio/read_until.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/asio/streambuf.hpp>
#include <boost/asio/use_awaitable.hpp>
#include <boost/asio/write.hpp>
#include <chrono>
#include <istream>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "control/control_protocol.h"
#include "control/control_relay.h"
#include "unit/support/fake_bus.h"

using namespace tiltgate;
using namespace tiltgate::test;
using namespace std::chrono_literals;
namespace asio = boost::asio;
using local = asio::local::stream_protocol;

namespace {

// The gateway's event loop with the relay on one end of a socket pair; the command's end is
// blocking, for a thread of the test's.
struct RelayPair {
  asio::io_context io;
  local::socket gateway_end{io};
  asio::io_context command_io;
  local::socket command_end{command_io};
  asio::streambuf input;
  ControlRelayFramer relay{gateway_end, input};
  asio::streambuf command_input;

  RelayPair() { asio::local::connect_pair(gateway_end, command_end); }

  // The next line the command reads.
  std::string command_reads() {
    asio::read_until(command_end, command_input, '\n');
    std::string line;
    std::istream stream(&command_input);
    std::getline(stream, line);
    return line;
  }
  void command_says(const std::string& line) {
    asio::write(command_end, asio::buffer(line + "\n"));
  }

  // feed_async(bytes) on the event loop, with a timer ticking every 5 ms beside it: the
  // answer, and the ticks seen while it was awaited.
  std::pair<std::optional<bool>, int> feed_with_ticks(std::vector<std::uint8_t> bytes) {
    std::optional<bool> whole;
    int ticks = 0;
    bool ticking = true;
    asio::co_spawn(
        io, [&]() -> asio::awaitable<void> { whole = co_await relay.feed_async(bytes); },
        asio::detached);
    asio::co_spawn(
        io,
        [&]() -> asio::awaitable<void> {
          asio::steady_timer tick(io);
          while (!whole) {
            tick.expires_after(5ms);
            co_await tick.async_wait(asio::use_awaitable);
            if (!whole) ++ticks;
          }
          ticking = false;
        },
        asio::detached);
    REQUIRE(run_until(io, [&] { return whole.has_value() && !ticking; }, 5s));
    return {whole, ticks};
  }
};

const std::string kMore = control::format(control::CommandMessage{control::FramerAnswer{false}});
const std::string kDone = control::format(control::CommandMessage{control::FramerAnswer{true}});

}  // namespace

TEST_CASE("relay: the command is asked asynchronously, and the event loop goes on while it thinks") {
  RelayPair pair;
  CHECK(pair.relay.asks_asynchronously());
  std::vector<std::string> read;  // by the command
  std::thread command([&] {
    read.push_back(pair.command_reads());
    pair.command_says(kMore);
    read.push_back(pair.command_reads());
    std::this_thread::sleep_for(60ms);  // a slow command, within kAnswerWait
    pair.command_says(kDone);
  });
  CHECK(pair.feed_with_ticks({0xA0, 0xA1}).first == false);
  const auto [whole, ticks] = pair.feed_with_ticks({0xA2});
  command.join();
  CHECK(read == std::vector<std::string>{
                    control::format(control::GatewayMessage{control::Received{{0xA0, 0xA1}}}),
                    control::format(control::GatewayMessage{control::Received{{0xA2}}})});
  CHECK(whole == true);
  CHECK(ticks >= 5);  // a blocking question would have let none through
  CHECK_FALSE(pair.relay.broken());
}

TEST_CASE("relay: a command that does not answer in time is taken as gone, without holding the event loop") {
  RelayPair pair;
  const auto start = std::chrono::steady_clock::now();
  const auto [whole, ticks] = pair.feed_with_ticks({0x01});
  const auto waited = std::chrono::steady_clock::now() - start;
  CHECK(whole == false);
  CHECK(pair.relay.broken());
  CHECK(waited >= ControlRelayFramer::kAnswerWait);
  CHECK(ticks >= 10);  // the event loop ran throughout the wait
  // Every later chunk is refused at once, and the socket is left as it was for the session.
  CHECK(pair.feed_with_ticks({0x02}).first == false);
  CHECK(pair.gateway_end.is_open());
}

TEST_CASE("relay: reset is sent at once, and a command that is gone or answers something else breaks it") {
  {
    RelayPair pair;
    pair.relay.reset();
    CHECK_FALSE(pair.relay.broken());
    CHECK(pair.command_reads() == control::format(control::GatewayMessage{control::Reset{}}));
    std::thread command([&] {
      pair.command_reads();
      pair.command_says("hello /dev/ttyUSB0");  // not a framer's answer
    });
    CHECK(pair.feed_with_ticks({0x01}).first == false);
    command.join();
    CHECK(pair.relay.broken());
  }
  {
    RelayPair pair;
    pair.command_end.close();
    pair.relay.reset();
    CHECK(pair.relay.broken());
  }
  {
    RelayPair pair;  // asked synchronously: it would have to wait, so it does not answer
    CHECK_FALSE(pair.relay.feed(std::vector<std::uint8_t>{0x01}));
    CHECK(pair.relay.broken());
  }
}
