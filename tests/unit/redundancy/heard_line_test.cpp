// A standby's line (redundancy/heard_line.h) answers a poller's request with what the active
// master's same request got, each hearing once: never heard is "not sent", heard is taken with
// its reply and its time, a request taken already waits for its next hearing, a heard silence
// or a broken reply is a time-out, and a takeover ends every wait.
#include <doctest/doctest.h>

#include <boost/asio/co_spawn.hpp>
#include <boost/asio/detached.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/steady_timer.hpp>
#include <chrono>
#include <optional>
#include <vector>

#include "redundancy/heard_exchanges.h"
#include "redundancy/heard_line.h"
#include "unit/modbus_rtu/modbus_rtu_test_vectors.h"

using namespace tiltgate;
using namespace std::chrono_literals;
namespace asio = boost::asio;
using modbus_rtu::test::framed;

namespace {

using Bytes = std::vector<std::uint8_t>;

// The bus's own line, as far as a heard line asks it: its name.
class HeardBusLine final : public Line {
 public:
  asio::awaitable<Expected<Done, LineError>> transact(LineRequest) override {
    co_return Unexpected(LineError::closed);
  }
  std::uint64_t generation() const override { return 1; }
  bool is_open() const override { return false; }
  int retries() const override { return 0; }
  const std::string& name() const override { return name_; }
  const LineStats& stats() const override { return stats_; }
  const LineTiming& last_timing() const override { return timing_; }

 private:
  std::string name_ = "line1";
  LineStats stats_;
  LineTiming timing_;
};

// Takes whatever it is fed as the whole reply, and keeps it.
class TakeWholeReply final : public ReplyFramer {
 public:
  void reset() override { got.clear(); }
  bool feed(std::span<const std::uint8_t> bytes) override {
    got.assign(bytes.begin(), bytes.end());
    return true;
  }
  Bytes got;
};

HeardExchange heard_exchange_of(const Bytes& request, std::optional<Bytes> reply, bool reply_intact = true) {
  HeardExchange heard;
  heard.request.kind = HeardKind::request;
  heard.request.intact = true;
  heard.request.frame.time = std::chrono::system_clock::now();
  heard.request.frame.bytes = request;
  if (reply) {
    HeardFrame frame;
    frame.kind = HeardKind::reply;
    frame.intact = reply_intact;
    frame.frame.time = std::chrono::system_clock::now();
    frame.frame.bytes = *reply;
    heard.reply = frame;
  }
  return heard;
}

const Bytes kHeardRequest = framed("01 04 00 00 00 02");
const Bytes kHeardReply = framed("01 04 04 00 01 00 02");

struct HeardFixture {
  asio::io_context io;
  HeardBusLine bus;
  std::shared_ptr<HeardExchanges> heard =
      std::make_shared<HeardExchanges>(io.get_executor(), bus, 80us);
  std::unique_ptr<Line> line = heard->line_for_poller();
  TakeWholeReply framer;

  // One transaction on the heard line, run to its end.
  Expected<Done, LineError> transact() {
    std::optional<Expected<Done, LineError>> result;
    asio::co_spawn(io, [&]() -> asio::awaitable<void> {
      LineRequest request;
      request.bytes = kHeardRequest;
      request.framer = &framer;
      result = co_await line->transact(std::move(request));
    }, asio::detached);
    io.run_for(3s);
    io.restart();
    REQUIRE(result.has_value());
    return *result;
  }
  // Hears the exchange after `delay` while a transaction waits.
  void hear_later(std::chrono::milliseconds delay, HeardExchange heard_exchange) {
    auto timer = std::make_shared<asio::steady_timer>(io, delay);
    timer->async_wait([this, timer, heard_exchange](const boost::system::error_code&) {
      heard->on_exchange(heard_exchange);
    });
  }
};

}  // namespace

TEST_CASE("a standby's line: a request never heard is not sent, and sends nothing") {
  HeardFixture f;
  const auto got = f.transact();
  REQUIRE_FALSE(got);
  CHECK(got.error() == LineError::expired);
  CHECK(f.line->listens_only());
  CHECK(f.line->last_timing().bytes_out == 0);
}

TEST_CASE("a standby's line: a heard request is answered with its reply, dated when heard") {
  HeardFixture f;
  f.heard->on_exchange(heard_exchange_of(kHeardRequest, kHeardReply));
  const auto before = std::chrono::steady_clock::now();
  const auto got = f.transact();
  REQUIRE(got);
  CHECK(f.framer.got == kHeardReply);
  REQUIRE(f.line->last_timing().reply_at.has_value());
  CHECK(*f.line->last_timing().reply_at <= before + 5ms);
  CHECK(f.line->last_timing().bytes_in == kHeardReply.size());
}

TEST_CASE("a standby's line: a hearing is taken once, and the next poll waits for the next one") {
  HeardFixture f;
  f.heard->on_exchange(heard_exchange_of(kHeardRequest, kHeardReply));
  REQUIRE(f.transact());
  const Bytes second_reply = framed("01 04 04 00 03 00 04");
  f.hear_later(50ms, heard_exchange_of(kHeardRequest, second_reply));
  const auto started = std::chrono::steady_clock::now();
  REQUIRE(f.transact());
  CHECK(std::chrono::steady_clock::now() - started >= 40ms);
  CHECK(f.framer.got == second_reply);
}

TEST_CASE("a standby's line: a request heard once and taken is given up after a second") {
  HeardFixture f;
  f.heard->on_exchange(heard_exchange_of(kHeardRequest, kHeardReply));
  REQUIRE(f.transact());
  const auto started = std::chrono::steady_clock::now();
  const auto got = f.transact();
  REQUIRE_FALSE(got);
  CHECK(got.error() == LineError::expired);
  CHECK(std::chrono::steady_clock::now() - started >= HeardLine::kFirstRepeatWait - 50ms);
}

TEST_CASE("a standby's line: a heard silence or a broken reply is the sensor's time-out") {
  HeardFixture f;
  f.heard->on_exchange(heard_exchange_of(kHeardRequest, std::nullopt));
  auto got = f.transact();
  REQUIRE_FALSE(got);
  CHECK(got.error() == LineError::timeout);
  Bytes broken = kHeardReply;
  broken.back() ^= 0xFF;
  f.heard->on_exchange(heard_exchange_of(kHeardRequest, broken, false));
  got = f.transact();
  REQUIRE_FALSE(got);
  CHECK(got.error() == LineError::timeout);
  CHECK(f.line->last_timing().garbled);
}

TEST_CASE("a standby's line: taking the lines ends a wait at once") {
  HeardFixture f;
  f.heard->on_exchange(heard_exchange_of(kHeardRequest, kHeardReply));
  f.heard->on_exchange(heard_exchange_of(kHeardRequest, kHeardReply));
  REQUIRE(f.transact());
  auto timer = std::make_shared<asio::steady_timer>(f.io, 30ms);
  timer->async_wait([&f, timer](const boost::system::error_code&) { f.heard->stop_waits(); });
  const auto started = std::chrono::steady_clock::now();
  const auto got = f.transact();
  REQUIRE_FALSE(got);
  CHECK(got.error() == LineError::cancelled);
  CHECK(std::chrono::steady_clock::now() - started < 150ms);
}

TEST_CASE("what a standby heard: the last intact request's time, requests counted") {
  HeardFixture f;
  CHECK_FALSE(f.heard->last_request().has_value());
  HeardFrame request;
  request.kind = HeardKind::request;
  request.intact = true;
  request.frame.time = std::chrono::system_clock::now();
  request.frame.bytes = kHeardRequest;
  f.heard->on_frame(request);
  request.intact = false;  // a broken one is nobody's request
  f.heard->on_frame(request);
  CHECK(f.heard->requests_heard() == 1);
  CHECK(f.heard->last_request().has_value());
}
