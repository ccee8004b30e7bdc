// Retired (gateway/retired.h): what a reload replaced is freed once it says it is finished, at
// once when it already is, else at a look a second later; nothing before.
#include <doctest/doctest.h>

#include <boost/asio/io_context.hpp>
#include <chrono>
#include <memory>

#include "gateway/retired.h"
#include "unit/support/fake_bus.h"

using namespace tiltgate;
using namespace tiltgate::test;
using namespace std::chrono_literals;

namespace {

// Counts how many of its kind are alive.
struct Replaced {
  explicit Replaced(int& alive, bool finished) : alive(alive), done(finished) { ++alive; }
  ~Replaced() { --alive; }
  bool finished() const { return done; }
  int& alive;
  bool done;
};

}  // namespace

TEST_CASE("a replaced object already finished is freed when it is retired") {
  boost::asio::io_context io;
  Retired<Replaced> retired(io.get_executor());
  int alive = 0;
  retired.add(std::make_unique<Replaced>(alive, true));
  CHECK(alive == 0);
  CHECK(retired.size() == 0);
}

TEST_CASE("a replaced object still in use is kept, then freed within a second of finishing") {
  boost::asio::io_context io;
  Retired<Replaced> retired(io.get_executor());
  int alive = 0;
  auto object = std::make_unique<Replaced>(alive, false);
  Replaced& busy = *object;
  retired.add(std::move(object));
  io.run_for(1200ms);
  CHECK(alive == 1);  // still in use: kept, looked at again
  busy.done = true;
  CHECK(run_until(io, [&] { return alive == 0; }, std::chrono::seconds(5)));
  CHECK(retired.size() == 0);
}
