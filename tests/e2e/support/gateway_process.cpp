#include "e2e/support/gateway_process.h"

#include <arpa/inet.h>
#include <csignal>
#include <deque>
#include <fcntl.h>
#include <fstream>
#include <mutex>
#include <random>
#include <netinet/in.h>
#include <set>
#include <sstream>
#include <stdexcept>
#include <sys/file.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>

namespace tiltgate::test {

namespace {

std::string read_file(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

pid_t spawn(const std::vector<std::string>& args, const std::filesystem::path& out,
            const std::filesystem::path& err) {
  const pid_t pid = ::fork();
  if (pid != 0) return pid;
  const int out_fd = ::open(out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  const int err_fd = ::open(err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  ::dup2(out_fd, 1);
  ::dup2(err_fd, 2);
  const int null_fd = ::open("/dev/null", O_RDONLY);
  ::dup2(null_fd, 0);
  std::vector<char*> argv;
  std::string binary = TILTGATE_BINARY;
  argv.push_back(binary.data());
  std::vector<std::string> copy = args;
  for (auto& a : copy) argv.push_back(a.data());
  argv.push_back(nullptr);
  ::execv(binary.c_str(), argv.data());
  ::_exit(127);
}

int decode_status(int status) {
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  if (WIFSIGNALED(status)) return 128 + WTERMSIG(status);
  return -1;
}

}  // namespace

std::uint16_t free_tcp_port() {
  // A port below the kernel's ephemeral range (32768 up on Debian), so no connect() anywhere on
  // the machine takes it between its choice here and the gateway's bind (a test's own clients
  // did, in CI); claimed by an flock on /tmp/tiltgate-test-ports/PORT, held while the port is
  // one of this program's last 64, so test programs running side by side never choose the same
  // one; never handed out twice in one program.
  static std::mutex handed_out_mutex;
  static std::set<std::uint16_t> handed_out;
  static std::deque<int> claims_held;
  static std::mt19937 random{std::random_device{}()};
  std::lock_guard lock(handed_out_mutex);
  const std::filesystem::path claims = "/tmp/tiltgate-test-ports";
  std::error_code ignored;
  std::filesystem::create_directories(claims, ignored);
  std::filesystem::permissions(
      claims, std::filesystem::perms::all | std::filesystem::perms::sticky_bit, ignored);
  std::uniform_int_distribution<int> pick(20000, 32767);
  for (int attempt = 0; attempt < 1000; ++attempt) {
    const auto port = static_cast<std::uint16_t>(pick(random));
    if (handed_out.contains(port)) continue;
    const auto claim_path = claims / std::to_string(port);
    const int claim = ::open(claim_path.c_str(), O_RDONLY | O_CREAT | O_CLOEXEC, 0644);
    if (claim < 0) continue;
    if (::flock(claim, LOCK_EX | LOCK_NB) != 0) {
      ::close(claim);
      continue;
    }
    const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    addr.sin_port = htons(port);
    const bool bound = ::bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) == 0;
    ::close(fd);
    if (!bound) {
      ::close(claim);
      continue;
    }
    handed_out.insert(port);
    claims_held.push_back(claim);
    if (claims_held.size() > 64) {
      ::close(claims_held.front());
      claims_held.pop_front();
    }
    return port;
  }
  throw std::runtime_error("no free TCP port in 20000-32767");
}

TempDir::TempDir() {
  char tmpl[] = "/tmp/tiltgate-e2e-XXXXXX";
  if (::mkdtemp(tmpl) == nullptr) throw std::runtime_error("mkdtemp failed");
  path_ = tmpl;
}

TempDir::~TempDir() {
  std::error_code ignored;
  std::filesystem::remove_all(path_, ignored);
}

std::filesystem::path TempDir::write(const std::string& name, const std::string& text) const {
  const auto file = path_ / name;
  std::ofstream(file) << text;
  return file;
}

GatewayProcess::GatewayProcess(std::vector<std::string> args, const std::filesystem::path& log_dir)
    : stderr_path_(log_dir / "tiltgate.stderr"), stdout_path_(log_dir / "tiltgate.stdout") {
  pid_ = spawn(args, stdout_path_, stderr_path_);
}

GatewayProcess::~GatewayProcess() {
  if (pid_ > 0 && terminate(std::chrono::seconds(5)) == -1) {
    ::kill(pid_, SIGKILL);
    ::waitpid(pid_, nullptr, 0);
  }
}

bool GatewayProcess::running() {
  if (pid_ <= 0) return false;
  int status = 0;
  if (::waitpid(pid_, &status, WNOHANG) == pid_) {
    exit_code_ = decode_status(status);
    pid_ = -1;
    return false;
  }
  return true;
}

bool GatewayProcess::wait_listening(std::uint16_t port, std::chrono::seconds limit) {
  const auto deadline = std::chrono::steady_clock::now() + limit;
  while (std::chrono::steady_clock::now() < deadline) {
    if (!running()) return false;
    const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    addr.sin_port = htons(port);
    const bool ok = ::connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) == 0;
    ::close(fd);
    if (ok) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  return false;
}

int GatewayProcess::wait_exit(std::chrono::seconds limit) {
  const auto deadline = std::chrono::steady_clock::now() + limit;
  while (running() && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return running() ? -1 : exit_code_;
}

int GatewayProcess::terminate(std::chrono::seconds limit) {
  if (pid_ > 0) ::kill(pid_, SIGTERM);
  return wait_exit(limit);
}

bool GatewayProcess::signal(int signal) { return running() && ::kill(pid_, signal) == 0; }

std::string GatewayProcess::log() const { return read_file(stderr_path_); }
std::string GatewayProcess::output() const { return read_file(stdout_path_); }

CommandResult run_tiltgate(std::vector<std::string> args) {
  TempDir dir;
  GatewayProcess process(std::move(args), dir.path());
  const int code = process.wait_exit(std::chrono::seconds(20));
  return {code, process.output(), process.log()};
}

}  // namespace tiltgate::test
