// `tiltgate demo` as a controls engineer runs it: every family's demo bus, the Modbus RTU one
// included (its inclinometer described by the example device profile the demo writes into a
// private folder and removes at exit), and the mbpoll examples for each unit.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "e2e/support/gateway_process.h"
#include "e2e/support/mixed_plant.h"
#include "modbus_rtu/family.h"

using namespace tiltgate;
using namespace tiltgate::test;
using namespace std::chrono_literals;

namespace {

// TMPDIR for the children started meanwhile, restored after.
class TmpdirFor {
 public:
  explicit TmpdirFor(const std::filesystem::path& path) {
    if (const char* old = std::getenv("TMPDIR")) old_ = old;
    ::setenv("TMPDIR", path.c_str(), 1);
  }
  ~TmpdirFor() {
    if (old_) ::setenv("TMPDIR", old_->c_str(), 1);
    else ::unsetenv("TMPDIR");
  }

 private:
  std::optional<std::string> old_;
};

// The demo numbers its sensors from unit 1 in family order, skipping families without any.
int first_demo_unit_of(const FamilyDescriptor& wanted) {
  int unit = 1;
  for (const FamilyCommands* family : registered_family_commands()) {
    if (family->family == &wanted) return unit;
    unit += int(family->demo.sensors.size());
  }
  return 0;
}

std::string read_text(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

std::vector<std::filesystem::path> files_under(const std::filesystem::path& folder) {
  std::vector<std::filesystem::path> files;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(folder))
    if (entry.is_regular_file()) files.push_back(entry.path());
  return files;
}

// The demo's help once it is all out (it ends with "Ctrl-C stops.").
std::string whole_help(const GatewayProcess& demo) {
  const auto deadline = std::chrono::steady_clock::now() + 10s;
  std::string help = demo.output();
  while (help.find("Ctrl-C stops.") == std::string::npos &&
         std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(20ms);
    help = demo.output();
  }
  return help;
}

// The words of the help's first line that starts (after its indent) with `start`.
std::vector<std::string> line_words(const std::string& help, const std::string& start) {
  std::istringstream lines(help);
  for (std::string line; std::getline(lines, line);) {
    if (line.find_first_not_of(' ') == std::string::npos ||
        line.compare(line.find_first_not_of(' '), start.size(), start) != 0)
      continue;
    std::istringstream in(line);
    std::vector<std::string> words;
    for (std::string w; in >> w;) words.push_back(w);
    return words;
  }
  return {};
}

bool has(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

}  // namespace

TEST_CASE("tiltgate demo: Try lines first, commissioning through its own control socket, a clean stop") {
  TempDir dir;
  const std::filesystem::path tmp = dir.path() / "tmp";
  std::filesystem::create_directory(tmp);
  const std::uint16_t port = free_tcp_port();
  std::optional<GatewayProcess> demo;
  {
    TmpdirFor tmpdir(tmp);
    demo.emplace(std::vector<std::string>{"demo", "--port", std::to_string(port), "--http-port",
                                          "0"},
                 dir.path());
  }
  REQUIRE_MESSAGE(demo->wait_listening(port), demo->log());
  const std::string help = whole_help(*demo);
  INFO("help: " << help);
  INFO("log: " << demo->log());
  // The map only on request: the Try lines come first.
  CHECK(help.rfind("tiltgate demo: ", 0) == 0);
  CHECK_FALSE(has(help, "### Unit"));
  CHECK(has(help, "tiltgate demo --map"));

  // Its control socket is its own, in its temporary folder, and the printed command works.
  std::vector<std::string> info = line_words(help, "tiltgate info ");
  REQUIRE(info.size() > 2);
  const auto socket = std::find(info.begin(), info.end(), "--control-socket");
  REQUIRE(socket + 1 < info.end());
  CHECK(std::filesystem::path(*(socket + 1)).parent_path().parent_path() == tmp);
  CHECK_FALSE(has(demo->log(), "control socket off"));
  info.erase(info.begin());  // "tiltgate"
  const CommandResult commissioned = run_tiltgate(info);
  INFO("info: " << commissioned.out << commissioned.err);
  CHECK(commissioned.exit_code == 0);
  CHECK(has(commissioned.err, "through the running gateway"));
  CHECK(has(commissioned.out, "serial:"));

  // Stopped while its sensors are polled: none of them is said to have stopped answering.
  const auto stopping = std::chrono::steady_clock::now();
  CHECK(demo->terminate() == 0);
  const auto took = std::chrono::steady_clock::now() - stopping;
  MESSAGE("stopped in ", std::chrono::duration_cast<std::chrono::milliseconds>(took).count(),
          " ms");
  CHECK_FALSE(has(demo->log(), "stopped answering"));
  // A loose bound (it took 1.4 to 2 s, waiting for work a stop had cancelled).
  CHECK(took < 1s);
  CHECK(std::filesystem::is_empty(tmp));
}

TEST_CASE("tiltgate demo --map prints the register maps, then its Try lines") {
  TempDir dir;
  const std::uint16_t port = free_tcp_port();
  GatewayProcess demo({"demo", "--port", std::to_string(port), "--http-port", "0", "--map"},
                      dir.path());
  REQUIRE_MESSAGE(demo.wait_listening(port), demo.log());
  const std::string help = whole_help(demo);
  INFO("help: " << help);
  CHECK(help.rfind("### Unit 1: ", 0) == 0);
  CHECK(help.find("| input | 0 | 30001 |") < help.find("Try:"));
  CHECK_FALSE(has(help, "tiltgate demo --map"));
}

TEST_CASE("tiltgate demo serves the RTU inclinometer through the example profile and cleans up") {
  TempDir dir;
  const std::filesystem::path tmp = dir.path() / "tmp";
  std::filesystem::create_directory(tmp);
  const std::uint16_t port = free_tcp_port();
  const int unit = first_demo_unit_of(modbus_rtu::kFamily);
  REQUIRE(unit > 1);  // after the other families' sensors
  std::optional<GatewayProcess> demo;
  {
    TmpdirFor tmpdir(tmp);
    demo.emplace(std::vector<std::string>{"demo", "--port", std::to_string(port)}, dir.path());
  }
  REQUIRE_MESSAGE(demo->wait_listening(port), demo->log());

  ModbusClient client(port, unit);
  std::vector<std::uint16_t> words;
  const auto deadline = std::chrono::steady_clock::now() + 15s;
  while (std::chrono::steady_clock::now() < deadline) {
    words = client.input(0, 38);
    if (words.size() == 38 && (words[6] & 0x01) == 0x01) break;  // online
    std::this_thread::sleep_for(50ms);
  }
  REQUIRE_MESSAGE(words.size() == 38, demo->log());
  CHECK((words[6] & 0x01) == 0x01);
  CHECK(words[37] == modbus_rtu::kFamily.models[0].model_code);
  // The simulator's first slave: X = 1, Y = -1 degrees, swaying by 0.25 in the demo; the
  // 0.01-degree registers agree with the float ones.
  const float x = float_at(words, 0);
  const float y = float_at(words, 2);
  CHECK(std::abs(x - 1.0f) <= 0.2501f);
  CHECK(std::abs(y + 1.0f) <= 0.2501f);
  CHECK(std::abs(std::int16_t(words[4]) - 100.0f * x) <= 1.0f);
  CHECK(std::abs(std::int16_t(words[5]) - 100.0f * y) <= 1.0f);

  // The profile it reads is the example, byte for byte, in the demo's own folder, beside its
  // configuration file, the web console's users file of this run's accounts and its state
  // (the audit trail).
  std::vector<std::filesystem::path> written = files_under(tmp);
  std::erase_if(written, [&](const std::filesystem::path& file) {
    return file.lexically_relative(tmp).string().find("/state/") != std::string::npos;
  });
  std::sort(written.begin(), written.end(),
            [](const auto& a, const auto& b) { return a.filename() < b.filename(); });
  REQUIRE(written.size() == 3);
  CHECK(written[0].filename() == "demo.toml");
  CHECK(written[2].filename() == "users");
  CHECK(written[1].filename() == "rtu-inclinometer.toml");
  CHECK(read_text(written[1]) ==
        read_text(std::filesystem::path(TILTGATE_SOURCE_DIR) /
                  "examples/devices/rtu-inclinometer.toml"));

  // The help names the RTU unit in its mbpoll examples.
  const std::string help = demo->output();
  CHECK(help.find("-a " + std::to_string(unit) + " -t 3:float -B -r 1 -c 2") != std::string::npos);

  CHECK(demo->terminate() == 0);
  CHECK(std::filesystem::is_empty(tmp));
}

TEST_CASE("tiltgate demo gives no USB latency advice for its simulated buses' pseudo-terminals") {
  TempDir dir;
  const std::uint16_t port = free_tcp_port();
  GatewayProcess demo({"demo", "--port", std::to_string(port), "--http-port", "0"}, dir.path());
  REQUIRE_MESSAGE(demo.wait_listening(port), demo.log());
  // A pty has no latency timer to set: the low-latency outcome is a debug line, not info.
  CHECK_MESSAGE(demo.log().find("low-latency") == std::string::npos, demo.log());
  CHECK_MESSAGE(demo.log().find("latency timer") == std::string::npos, demo.log());
}
