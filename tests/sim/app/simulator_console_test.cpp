#include "app/simulator_console.h"

#include <doctest/doctest.h>
#include <fcntl.h>
#include <unistd.h>

#include <string>
#include <vector>

#include "sim/support/raw_tty_client.h"

namespace {

using tiltgate::BusSimulator;
using tiltgate::Done;
using tiltgate::Expected;
using tiltgate::SimulatorConsole;
using tiltgate::Unexpected;

// Takes "ok" and nothing else, and remembers every line it was given.
class RecordingSimulator final : public BusSimulator {
 public:
  Expected<Done, std::string> start() override { return Done{}; }
  void stop() override {}
  const std::string& slave_path() const override { return path_; }
  std::size_t sensor_count() const override { return 0; }
  std::string what() const override { return "recording sensor(s)"; }
  Expected<Done, std::string> command(std::string_view line) override {
    lines.emplace_back(line);
    if (line == "ok") return Done{};
    return Unexpected{"not ok: " + std::string(line)};
  }
  std::vector<std::string> lines;

 private:
  std::string path_;
};

struct Pipe {
  int read = -1, write = -1;
  Pipe() { REQUIRE(::pipe2(&read, O_CLOEXEC) == 0); }
  ~Pipe() {
    if (read >= 0) ::close(read);
    if (write >= 0) ::close(write);
  }
  void send(const std::string& text) const {
    REQUIRE(::write(write, text.data(), text.size()) == ssize_t(text.size()));
  }
};

}  // namespace

TEST_CASE("the simulator console passes each piped line to the simulator and answers it") {
  boost::asio::io_context io;
  RecordingSimulator simulator;
  std::vector<std::string> answers;
  Pipe pipe;
  SimulatorConsole console(io, simulator, pipe.read,
                           [&](const std::string& answer) { answers.push_back(answer); });
  REQUIRE(console.start());
  pipe.send("ok\nbad\r\n");
  pipe.send("o");  // a line in pieces is one line
  REQUIRE(tiltgate::test::run_until(io, [&] { return answers.size() == 2; }));
  pipe.send("k\n");
  REQUIRE(tiltgate::test::run_until(io, [&] { return answers.size() == 3; }));
  CHECK(simulator.lines == std::vector<std::string>{"ok", "bad", "ok"});
  CHECK(answers == std::vector<std::string>{"ok", "error: not ok: bad", "ok"});

  // End of input: no more reads, and the loop runs out of work on its own.
  ::close(pipe.write);
  pipe.write = -1;
  io.restart();
  CHECK(io.run_for(std::chrono::seconds(2)) >= 0);
  CHECK(io.stopped());
}

TEST_CASE("the simulator console stops at stop() with its read pending") {
  boost::asio::io_context io;
  RecordingSimulator simulator;
  Pipe pipe;
  SimulatorConsole console(io, simulator, pipe.read, [](const std::string&) {});
  REQUIRE(console.start());
  io.run_for(std::chrono::milliseconds(20));
  CHECK_FALSE(io.stopped());  // waiting for a line
  console.stop();
  io.restart();
  io.run_for(std::chrono::seconds(2));
  CHECK(io.stopped());
  CHECK(simulator.lines.empty());
}

TEST_CASE("the simulator console does not read a file or /dev/null") {
  boost::asio::io_context io;
  RecordingSimulator simulator;
  const int null = ::open("/dev/null", O_RDONLY | O_CLOEXEC);
  REQUIRE(null >= 0);
  SimulatorConsole console(io, simulator, null, [](const std::string&) {});
  CHECK_FALSE(console.start());
  ::close(null);
}

TEST_CASE("a line longer than any command ends the simulator console") {
  boost::asio::io_context io;
  RecordingSimulator simulator;
  Pipe pipe;
  SimulatorConsole console(io, simulator, pipe.read, [](const std::string&) {});
  REQUIRE(console.start());
  pipe.send(std::string(4096, 'a'));
  io.run_for(std::chrono::seconds(2));
  CHECK(io.stopped());  // the read failed: no more reads
  CHECK(simulator.lines.empty());
}
