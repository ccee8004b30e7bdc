#include "control/control_server.h"

#include <boost/asio/co_spawn.hpp>
#include <boost/asio/read_until.hpp>
#include <boost/asio/redirect_error.hpp>
#include <boost/asio/streambuf.hpp>
#include <boost/asio/use_awaitable.hpp>
#include <boost/asio/write.hpp>
#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fmt/format.h>
#include <istream>
#include <spdlog/spdlog.h>
#include <sys/stat.h>
#include <unistd.h>
#include <utility>

#include "audit/audit_trail.h"
#include "control/carried_change.h"
#include "control/control_protocol.h"
#include "control/setting_claim.h"
#include "control/control_relay.h"
#include "control/peer_identity.h"
#include "device_server/port_url.h"

namespace tiltgate {

namespace asio = boost::asio;
using local = asio::local::stream_protocol;

namespace {

// The same tty however it is named: /dev/serial/by-id/... and /dev/ttyUSB0 compare equal; the
// same device server port however it is reached: its host without case and its TCP port,
// tcp:// or rfc2217:// (the port takes one client: the gateway's).
std::string canonical_port(const std::string& port) {
  if (const auto address = parse_port(port); address && address->over_network()) {
    std::string endpoint = address->endpoint();
    std::transform(endpoint.begin(), endpoint.end(), endpoint.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    return endpoint;
  }
  std::error_code ec;
  const auto path = std::filesystem::weakly_canonical(port, ec);
  return ec ? port : path.string();
}

// Whether a gateway is listening on `path` now.
bool someone_listens(const std::string& path, asio::any_io_executor executor) {
  local::socket probe(executor);
  boost::system::error_code ec;
  probe.connect(local::endpoint(path), ec);
  return !ec;
}

// Takes the message formatted: g++ 12 destroys a temporary in a co_await expression twice, so
// callers format into a named string first.
asio::awaitable<bool> send(local::socket& socket, std::string line) {
  line += '\n';
  boost::system::error_code ec;
  co_await asio::async_write(socket, asio::buffer(line),
                             asio::redirect_error(asio::use_awaitable, ec));
  co_return !ec;
}

}  // namespace

ControlServer::ControlServer(asio::any_io_executor executor, std::string path,
                             std::vector<ServedBus> buses)
    : executor_(executor), path_(std::move(path)), buses_(std::move(buses)), acceptor_(executor) {}

ControlServer::~ControlServer() { stop(); }

Expected<Done, std::string> ControlServer::start() {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::path folder = fs::path(path_).parent_path();
  if (!folder.empty() && !fs::exists(folder, ec)) {
    fs::create_directories(folder, ec);
    if (ec) return Unexpected{fmt::format("cannot create {}: {}", folder.string(), ec.message())};
  }
  if (fs::exists(fs::symlink_status(path_, ec))) {
    if (someone_listens(path_, executor_))
      return Unexpected{fmt::format("{}: another gateway is listening there", path_)};
    if (!fs::is_socket(fs::symlink_status(path_, ec)))
      return Unexpected{fmt::format("{}: exists and is not a socket; not replacing it", path_)};
    fs::remove(path_, ec);  // stale: its gateway was killed
  }
  boost::system::error_code error;
  acceptor_.open(local(), error);
  if (!error) bind_for_owner_and_group(error);
  if (!error) acceptor_.listen(asio::socket_base::max_listen_connections, error);
  if (error) {
    acceptor_.close();
    return Unexpected{fmt::format("cannot listen on {}: {}", path_, error.message())};
  }
  listening_ = true;
  spawn(accept_loop());
  return Done{};
}

void ControlServer::bind_for_owner_and_group(boost::system::error_code& error) {
  // Connecting lets a program move sensors and change their settings: owner and group only,
  // from the instant the file exists (a chmod after bind leaves a moment when anyone may
  // connect). bind() makes the file 0777 less the umask, so the umask is narrowed around it.
  // The umask is the process's: the other threads then (the Modbus TCP connections' and
  // libmosquitto's) make no files, and one that did would only get fewer rights.
  const mode_t before = ::umask(0117);
  acceptor_.bind(local::endpoint(path_), error);
  ::umask(before);
}

void ControlServer::spawn(asio::awaitable<void> work) {
  ++coroutines_;
  asio::co_spawn(executor_, std::move(work), [this](std::exception_ptr) { --coroutines_; });
}

void ControlServer::stop() {
  if (!listening_) return;
  listening_ = false;
  boost::system::error_code ec;
  acceptor_.close(ec);
  for (auto& weak : sessions_)
    if (auto socket = weak.lock()) socket->close(ec);
  sessions_.clear();
  std::error_code removed;
  std::filesystem::remove(path_, removed);
}

asio::awaitable<void> ControlServer::accept_loop() {
  while (listening_) {
    boost::system::error_code ec;
    local::socket socket = co_await acceptor_.async_accept(asio::redirect_error(asio::use_awaitable, ec));
    if (ec) {
      if (!listening_) co_return;
      continue;
    }
    std::erase_if(sessions_, [](const auto& weak) { return weak.expired(); });
    if (sessions_.size() >= kMaxSessions) {
      const std::string refusal =
          control::format(control::GatewayMessage{control::Refused{fmt::format(
              "the gateway already serves {} commissioning commands; try again later",
              kMaxSessions)}}) + "\n";
      asio::write(socket, asio::buffer(refusal), ec);
      continue;
    }
    spawn(session(std::move(socket)));
  }
}

ControlServer::ServedBus* ControlServer::find_bus(const std::string& port_or_name) {
  const std::string wanted = canonical_port(port_or_name);
  for (ServedBus& bus : buses_)
    if (bus.config.name == port_or_name || canonical_port(bus.config.port) == wanted) return &bus;
  return nullptr;
}

std::string ControlServer::bus_list() const {
  std::string list;
  for (const ServedBus& bus : buses_)
    list += fmt::format("{}{} on {}", list.empty() ? "" : ", ", bus.config.name, bus.config.port);
  return list.empty() ? "none" : list;
}

namespace {

std::string formatted(const control::GatewayMessage& message) { return control::format(message); }

// A setting's outcome as the audit trail words it (audit/audit_record.h).
std::string audit_result(const control::SettingChanged& changed) {
  if (changed.nak) return fmt::format("nak 0x{:02X}", *changed.nak);
  return changed.timeout ? "timeout" : "ack";
}

// `as WHO`: the session's changes are recorded as WHO's from now on. Only a process of the
// gateway's own user (the web console) may say so: anyone else could hide behind a name.
std::string act_for(const std::string& who, bool own_user, WriteOrigin& by) {
  if (!own_user)
    return formatted(control::Refused{"as: only a process of the gateway's own user may act "
                                      "for someone else"});
  by.who = who + " (via the control socket)";
  return formatted(control::Followed{});
}

}  // namespace

asio::awaitable<void> ControlServer::session(local::socket accepted) {
  auto socket = std::make_shared<local::socket>(std::move(accepted));
  sessions_.push_back(socket);
  // Who connected, for the log line of a sensor it moves and the audit trail.
  WriteOrigin by{"control socket", peer_identity(socket->native_handle())};
  const bool own_user = peer_uid(socket->native_handle()) == ::geteuid();
  asio::streambuf input(control::kMaxLine);
  ServedBus* bus = nullptr;
  std::vector<std::uint32_t> held;  // addresses this session holds; released when it ends
  // How its latest transaction since its last `setting` report ended (control/setting_claim.h).
  control::CarriedOutcome carried = control::CarriedOutcome::none;
  // The change its latest changing transaction carried, until a report names it or it is
  // recorded as it is (control/carried_change.h). Reads between the change and its report (a
  // read-back, the lock) leave it waiting; the same request again (the command's retry)
  // replaces it.
  std::optional<control::CarriedChange> change;
  auto record_change = [&] {
    if (change && bus != nullptr)
      bus->scheduler->note_carried(change->address, std::move(change->function),
                                   std::move(change->data), std::move(change->result),
                                   change->unix_ms, by);
    change.reset();
  };
  while (listening_) {
    boost::system::error_code ec;
    co_await asio::async_read_until(*socket, input, '\n',
                                    asio::redirect_error(asio::use_awaitable, ec));
    if (ec) break;  // gone, closed by stop(), or a line longer than kMaxLine
    std::string line;
    std::istream stream(&input);
    std::getline(stream, line);
    // Each answer is formatted into `reply` before it is sent (see send()); `done` ends the
    // session after it.
    std::string reply;
    bool done = false;
    auto message = control::parse_command(line);
    // A report after the transaction names its change: one record, the report's.
    const bool keeps_change =
        message && (std::holds_alternative<control::SettingChanged>(*message) ||
                    std::holds_alternative<control::Follow>(*message) ||
                    std::holds_alternative<control::Transact>(*message));
    if (!keeps_change) record_change();
    if (!message) {
      reply = formatted(control::Refused{message.error()});
      done = true;
    } else if (const auto* acting = std::get_if<control::ActingFor>(&*message)) {
      reply = act_for(acting->who, own_user, by);
    } else if (const auto* hello = std::get_if<control::Hello>(&*message)) {
      bus = find_bus(hello->port);
      reply = bus ? formatted(control::BusGranted{bus->config.name, bus->config.protocol,
                                                  bus->config.baud})
                  : formatted(control::Refused{fmt::format(
                        "the gateway has no bus on {} (its buses: {})", hello->port, bus_list())});
    } else if (bus == nullptr) {
      reply = formatted(control::Refused{"ask for a bus first (hello PORT)"});
      done = true;
    } else if (const auto* transact = std::get_if<control::Transact>(&*message)) {
      std::optional<control::CarriedChange> asked;
      if (bus->protocol != nullptr) asked = control::change_asked(*bus->protocol, transact->bytes);
      const bool changing = asked.has_value();
      if (changing) {
        if (change && !control::same_request(*change, *asked)) record_change();
        change = std::move(asked);
      }
      // [audit] when_full = "refuse": no change the trail cannot keep on disk.
      if (AuditTrail* trail = bus->scheduler->audit();
          changing && trail != nullptr && !trail->accepts_changes()) {
        change->result = fmt::format("refused: {}", kAuditRefusesChanges);
        change->unix_ms = control::now_unix_ms();
        record_change();
        carried = control::CarriedOutcome::not_sent;
        reply = formatted(control::Refused{std::string(kAuditRefusesChanges)});
        if (!co_await send(*socket, std::move(reply))) break;
        continue;
      }
      ControlRelayFramer relay(*socket, input);
      LineRequest request{transact->bytes,    transact->address_bytes,
                          transact->expects_reply ? &relay : nullptr,
                          transact->timeout,  transact->retries,
                          transact->settle,   transact->late_guard};
      const SteadyClock::time_point deadline = SteadyClock::now() + kQueueDeadline;
      CommandExchangeResult result =
          co_await bus->scheduler->exchange_for_command(std::move(request), deadline);
      control::Ended ended;
      if (!result.done) ended.error = result.done.error();
      ended.busy = result.expired;
      ended.timing = result.timing;
      ended.generation = result.generation;
      carried = control::carried_outcome(ended);
      if (changing) {
        change->result = control::carried_result(*bus->protocol, ended,
                                                 transact->expects_reply, relay.received());
        change->unix_ms = control::now_unix_ms();
      }
      reply = formatted(ended);
      if (relay.broken()) break;  // the command stopped answering mid-transaction
    } else if (const auto* follow = std::get_if<control::Follow>(&*message)) {
      // The move's own record stands for the transaction that made it.
      if (change && change->address != follow->from) record_change();
      change.reset();
      const auto moved = bus->scheduler->follow_address(follow->from, follow->to, by);
      std::erase(held, follow->from);
      reply = formatted(control::Followed{moved ? bus->config.name + "/" + *moved : ""});
    } else if (const auto* hold = std::get_if<control::Hold>(&*message)) {
      const auto sensor = bus->scheduler->hold(hold->address, SteadyClock::now() + kMaxHold);
      if (sensor) held.push_back(hold->address);
      reply = formatted(control::Followed{sensor ? bus->config.name + "/" + *sensor : ""});
    } else if (const auto* changed = std::get_if<control::SettingChanged>(&*message)) {
      // Recorded either way; only a report a transaction stands behind changes what is shown,
      // and its record then stands for the transaction's.
      const auto refusal = control::setting_claim_refusal(std::exchange(carried, {}), *changed);
      if (refusal) record_change();
      change.reset();
      const auto sensor = bus->scheduler->note_setting(
          changed->address, WriteTarget{changed->setting}, changed->value,
          refusal ? "refused: " + *refusal : audit_result(*changed), by);
      reply = refusal ? formatted(control::Refused{"setting: " + *refusal})
                      : formatted(control::Followed{sensor ? bus->config.name + "/" + *sensor
                                                           : ""});
    } else if (const auto* release = std::get_if<control::Release>(&*message)) {
      bus->scheduler->release(release->address);
      std::erase(held, release->address);
      reply = formatted(control::Followed{});
    } else {
      reply = formatted(control::Refused{"a framer's answer outside a transaction"});
      done = true;
    }
    if (!co_await send(*socket, std::move(reply)) || done) break;
  }
  record_change();
  // A command that went away mid re-address must not leave a sensor unpolled.
  if (bus != nullptr && listening_)
    for (const std::uint32_t address : held) bus->scheduler->release(address);
  boost::system::error_code ignored;
  socket->close(ignored);
}

}  // namespace tiltgate
