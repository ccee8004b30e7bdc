// build/tiltgate info on a line behind a real device server: Debian's ser2net serving a Rieker
// simulator's pseudo-terminal, raw (the rate is ser2net's setting) and in RFC 2217 mode (the
// rate is the command's: ser2net starts the port at another one, and the simulator answers
// only at the rate its sensors are set to). Nothing in the commissioning commands may insist
// on a tty.
#include <doctest/doctest.h>

#include <fcntl.h>
#include <netinet/in.h>
#include <signal.h>
#include <spawn.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <arpa/inet.h>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "e2e/support/front_end.h"
#include "e2e/support/gateway_process.h"
#include "e2e/support/simulator_process.h"

using namespace tiltgate;
using namespace tiltgate::test;
using namespace std::chrono_literals;

extern char** environ;

namespace {

// ser2net in the foreground on 127.0.0.1:port, with one connection to `tty` as `yaml_accepter`
// says ("tcp" or "telnet(rfc2217),tcp"), the port's own framing `serial_setting`.
class Ser2net {
 public:
  Ser2net(const TempDir& dir, const std::string& accepter, const std::string& tty,
          const std::string& serial_setting)
      : port_(free_tcp_port()), log_(dir.path() / "ser2net.log") {
    const auto config = dir.write(
        "ser2net.yaml", "connection: &line\n  accepter: " + accepter + ",127.0.0.1," +
                            std::to_string(port_) + "\n  connector: serialdev," + tty + "," +
                            serial_setting + ",local\n");
    const std::string pid_file = (dir.path() / "ser2net.pid").string();
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, log_.c_str(),
                                     O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
    std::vector<std::string> args{"ser2net", "-n", "-u", "-c", config.string(), "-P", pid_file};
    std::vector<char*> argv;
    for (std::string& arg : args) argv.push_back(arg.data());
    argv.push_back(nullptr);
    const int spawned = posix_spawnp(&pid_, "ser2net", &actions, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    REQUIRE_MESSAGE(spawned == 0, "ser2net cannot be started: install Debian's ser2net "
                                  "(scripts/setup names it)");
    REQUIRE_MESSAGE(wait_listening(), log());
  }
  ~Ser2net() {
    ::kill(pid_, SIGTERM);
    int status = 0;
    ::waitpid(pid_, &status, 0);
  }
  Ser2net(const Ser2net&) = delete;
  Ser2net& operator=(const Ser2net&) = delete;

  std::string url(const std::string& scheme) const {
    return scheme + "://127.0.0.1:" + std::to_string(port_);
  }
  std::string log() const {
    std::ifstream in(log_);
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
  }

 private:
  // Listening once a connect succeeds (ser2net drops that probe, as it is meant to).
  bool wait_listening() const {
    const auto deadline = std::chrono::steady_clock::now() + 10s;
    while (std::chrono::steady_clock::now() < deadline) {
      const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
      sockaddr_in address{};
      address.sin_family = AF_INET;
      address.sin_port = htons(port_);
      address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
      const bool up = ::connect(fd, reinterpret_cast<sockaddr*>(&address), sizeof address) == 0;
      ::close(fd);
      if (up) return true;
      std::this_thread::sleep_for(20ms);
    }
    return false;
  }

  std::uint16_t port_;
  std::filesystem::path log_;
  pid_t pid_ = -1;
};

bool has_line(const std::string& out, const std::string& line) {
  return out.find(line + "\n") != std::string::npos;
}

}  // namespace

TEST_CASE("info reads a sensor behind ser2net over raw TCP and over RFC 2217") {
  // The sensor answers only at 38400 baud (a rate ser2net can set on a pty).
  SimulatorProcess sim({"rieker", "--sensors", "h6:223", "--baud", "38400"});

  SUBCASE("raw: ser2net's port is set to the sensor's rate on its own") {
    TempDir dir;
    Ser2net server(dir, "tcp", sim.tty(), "38400n81");
    const auto info = run_command({"info", "--port", server.url("tcp"), "--protocol", "rieker",
                                   "--baud", "38400", "--address", "223", "--control-socket",
                                   "/nonexistent/control.sock"});
    INFO(info.out << info.err << server.log());
    CHECK(info.exit_code == 0);
    CHECK(has_line(info.out, "serial:     9600223"));
  }
  SUBCASE("RFC 2217: ser2net starts at 9600 and the command sets 38400") {
    TempDir dir;
    Ser2net server(dir, "telnet(rfc2217),tcp", sim.tty(), "9600n81");
    const auto info = run_command({"info", "--port", server.url("rfc2217"), "--protocol",
                                   "rieker", "--baud", "38400", "--address", "223",
                                   "--control-socket", "/nonexistent/control.sock"});
    INFO(info.out << info.err << server.log());
    CHECK(info.exit_code == 0);
    CHECK(has_line(info.out, "serial:     9600223"));
    // At 9600, which the command sets now, the sensor does not answer: the rate set over RFC
    // 2217 is what made it answer above.
    const auto wrong = run_command({"info", "--port", server.url("rfc2217"), "--protocol",
                                    "rieker", "--baud", "9600", "--address", "223",
                                    "--control-socket", "/nonexistent/control.sock"});
    INFO(wrong.out << wrong.err);
    CHECK(wrong.exit_code == 1);
  }
}
