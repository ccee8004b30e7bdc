// What a Modbus TCP server is told ([server] in the config), and the copy of it in force: a
// reload (ModbusTcpServer::apply) replaces that copy all at once while connections on other
// threads read it request by request.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

#include "config/address_allow_list.h"
#include "config/tls_role_access.h"
#include "doors/log_throttle.h"
#include "modbus_tcp/modbus_stream.h"

namespace tiltgate {

struct ModbusServerOptions {
  std::string listen = "0.0.0.0";  // an IP address literal (IPv4 or IPv6)
  std::uint16_t port = 502;        // 0 picks a free port (tests); see local_port()
  bool plain_tcp = true;           // false: TLS only
  // Modbus/TCP Security beside (or instead of) plain TCP, on `listen`:tls->port; TLS clients
  // share every limit, list and time-out below, and the handshake must end within
  // request_timeout.
  std::optional<ModbusTlsOptions> tls;
  // At max_clients a new client replaces the one idle longest, else it is accepted and closed
  // at once (doors/connection_admission.h); an address holding max_clients_per_host replaces
  // its own connection idle longest, else it is closed.
  int max_clients = 32;
  int max_clients_per_host = 8;
  std::chrono::milliseconds idle_timeout{60000};    // no request for this long: closed
  std::chrono::milliseconds request_timeout{5000};  // a request (or its reply) stuck this long
                                                    // since its first byte: closed
  // A request with the handler (a write, a pass-through, anything not answered from the
  // cache) is answered 0x0B after this long, and the handler's late reply dropped: the handler
  // has deadlines of its own (write_timeout_ms), so this is a backstop no connection waits past.
  std::chrono::milliseconds handler_timeout{15000};
  // Requests a second the server answers, from every client together (across every server
  // sharing one SharedRateLimit) and from each connection; a request beyond them waits for its
  // turn (doors/request_rate.h). 0: no limit.
  double max_requests_per_s = 0;
  double max_client_requests_per_s = 0;
  AddressAllowList allow;        // other clients are closed at accept
  AddressAllowList write_allow;  // other clients' writes (any function but a read) get 0x01
  // A TLS client's writes get 0x01 too when its certificate's role may only read.
  TlsRoleAccess tls_roles;
  LogThrottleOptions problem_log;  // clients closed for cause: a few lines per address, then counts
};

// The options in force, from any thread: replace() swaps in a whole new set at once, and every
// reader finds it at its next read. Each options set is immutable once in force, so a reader
// keeps its pointer as long as it likes.
class ModbusOptionsInForce {
 public:
  explicit ModbusOptionsInForce(ModbusServerOptions options);
  ModbusOptionsInForce(const ModbusOptionsInForce&) = delete;
  ModbusOptionsInForce& operator=(const ModbusOptionsInForce&) = delete;

  std::shared_ptr<const ModbusServerOptions> current() const;
  void replace(ModbusServerOptions options);

  // One reader's copy (a connection's, used on its own thread only). A request reads the
  // options several times: this costs one atomic load each, and a lock only after replace()
  // changed them.
  class Reader {
   public:
    explicit Reader(const ModbusOptionsInForce& source) : source_(source) {}
    const ModbusServerOptions& latest();

   private:
    const ModbusOptionsInForce& source_;
    std::shared_ptr<const ModbusServerOptions> options_;
    std::uint64_t seen_ = 0;  // the generation options_ is of
  };

 private:
  mutable std::mutex mutex_;  // guards the pointer only
  std::shared_ptr<const ModbusServerOptions> options_;
  std::atomic<std::uint64_t> generation_{1};  // +1 by every replace()
};

}  // namespace tiltgate
