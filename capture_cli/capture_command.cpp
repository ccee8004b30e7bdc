#include "capture_cli/capture_command.h"

#include <boost/asio/co_spawn.hpp>
#include <boost/asio/detached.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/signal_set.hpp>
#include <csignal>
#include <fmt/format.h>
#include <fstream>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>

#include "capture/frame_json.h"
#include "capture/pcapng.h"
#include "capture_cli/listen_capture.h"
#include "config/config_loader.h"
#include "control/gateway_command.h"

namespace tiltgate {

namespace {

struct CaptureOptions {
  std::string bus;
  std::string config;
  std::string control_socket;
  std::int64_t seconds = 0;
  bool last = false;
  std::string port;
  std::string protocol;
  std::uint32_t baud = 0;
  std::string parity;
  int stop_bits = 0;
  std::string output;
};

// Where the pcapng goes: a file, or stdout for a pipe into Wireshark, each packet flushed as
// it comes so a live capture shows at once.
class PcapngOutput {
 public:
  explicit PcapngOutput(const std::string& path) {
    if (path == "-") {
      out_ = &std::cout;
    } else {
      file_.open(path, std::ios::binary | std::ios::trunc);
      out_ = &file_;
    }
  }
  bool open() const { return out_->good(); }
  // False once the reader went away (Wireshark closed) or the disk refused.
  bool write(const std::string& bytes) {
    out_->write(bytes.data(), std::streamsize(bytes.size()));
    out_->flush();
    return out_->good();
  }

 private:
  std::ofstream file_;
  std::ostream* out_ = nullptr;
};

int usage_error(const std::string& message) {
  std::cerr << "tiltgate capture: " << message << "\nRun with --help for more information.\n";
  return 2;
}

// The control socket: --control-socket, else the configuration's, else the default.
Expected<std::string, std::string> control_socket_of(const CaptureOptions& o,
                                                     FamilyList families) {
  if (!o.control_socket.empty()) return o.control_socket;
  if (o.config.empty()) return std::string(kDefaultControlSocket);
  auto loaded = load_config_file(o.config, families);
  if (!loaded) {
    std::string why;
    for (const ConfigError& e : loaded.error())
      why += "\n  " + e.to_string();
    return Unexpected{fmt::format("{} is not a configuration the gateway would run:{}", o.config,
                                  why)};
  }
  return loaded->server.control_socket;
}

int capture_through_gateway(const CaptureOptions& o, FamilyList families) {
  const auto socket = control_socket_of(o, families);
  if (!socket) {
    std::cerr << "tiltgate capture: " << socket.error() << "\n";
    return 1;
  }
  boost::asio::io_context io;
  auto gateway = GatewayCommand::connect(io.get_executor(), *socket, o.bus);
  if (!gateway) {
    std::cerr << "tiltgate capture: " << gateway.error().message << "\n";
    return 1;
  }
  PcapngOutput output(o.output);
  if (!output.open()) {
    std::cerr << fmt::format("tiltgate capture: cannot write {}\n", o.output);
    return 1;
  }
  std::signal(SIGPIPE, SIG_IGN);  // a reader that goes away is a write error, not a kill
  nlohmann::json request{{"command", "capture"}};
  if (o.last)
    request["last"] = true;
  else
    request["seconds"] = o.seconds;
  std::uint64_t frames = 0;
  std::uint64_t missed = 0;
  const control::BusGranted bus = (*gateway)->bus();
  const ProtocolDescriptor* protocol = find_protocol(families, bus.protocol).protocol;
  const PcapngFormat format = protocol ? pcapng_format_of(*protocol) : PcapngFormat{};
  bool header_written = false;
  bool failed = false;
  int exit_code = 1;
  boost::asio::signal_set signals(io, SIGINT, SIGTERM);
  std::function<void(const boost::system::error_code&, int)> on_signal =
      [&](const boost::system::error_code& ec, int) {
        if (ec) return;
        (*gateway)->stop();
        signals.async_wait(on_signal);  // a second Ctrl-C stops waiting for the gateway
      };
  signals.async_wait(on_signal);
  const auto on_event = [&](const std::string& text) {
    const nlohmann::json event = nlohmann::json::parse(text, nullptr, false);
    const std::string kind = event.is_object() ? event.value("event", "") : "";
    if (kind == "capture") {
      header_written = output.write(pcapng_header("tiltgate " TILTGATE_VERSION,
                                                  event.value("bus", o.bus)));
    } else if (kind == "frame" && header_written && !failed) {
      auto frame = frame_from_json(event);
      if (!frame) {
        std::cerr << "tiltgate capture: the gateway sent a frame this command cannot read ("
                  << frame.error() << ")\n";
        return;
      }
      ++frames;
      if (!output.write(pcapng_packet(*frame, format))) {
        failed = true;
        (*gateway)->stop();
      }
    } else if (kind == "missed") {
      missed += event.value("frames", std::uint64_t{0});
    } else if (kind == "error") {
      std::cerr << "tiltgate capture: " << event.value("message", text) << "\n";
    }
  };
  boost::asio::co_spawn(
      io,
      [&]() -> boost::asio::awaitable<void> {
        auto ran = co_await (*gateway)->run(request.dump(), on_event);
        signals.cancel();
        if (!ran) {
          std::cerr << "tiltgate capture: " << ran.error() << "\n";
          co_return;
        }
        exit_code = *ran;
      },
      boost::asio::detached);
  io.run();
  if (failed) {
    std::cerr << fmt::format("tiltgate capture: stopped: {} cannot be written any more\n",
                             o.output == "-" ? std::string("stdout") : o.output);
    return 1;
  }
  std::cerr << fmt::format("tiltgate capture: {} frame(s) of bus {} ({}){}\n", frames, bus.name,
                           bus.protocol,
                           missed > 0 ? fmt::format(", {} missed (the reader was too slow)",
                                                    missed)
                                      : std::string());
  return exit_code;
}

int capture_listening(const CaptureOptions& o, FamilyList families) {
  const ProtocolEntry protocol = find_protocol(families, o.protocol);
  if (protocol.protocol == nullptr) return usage_error("--protocol: no protocol " + o.protocol);
  ListenCaptureOptions listen;
  listen.port = o.port;
  listen.protocol = protocol.protocol;
  listen.baud = o.baud;
  listen.parity = o.parity;
  listen.stop_bits = o.stop_bits;
  listen.duration = std::chrono::seconds(o.seconds);
  PcapngOutput output(o.output);
  if (!output.open()) {
    std::cerr << fmt::format("tiltgate capture: cannot write {}\n", o.output);
    return 1;
  }
  std::signal(SIGPIPE, SIG_IGN);
  const PcapngFormat format = pcapng_format_of(*protocol.protocol);
  bool header_written = false;
  return run_listen_capture(listen, [&](const CapturedFrame& frame) {
    if (!header_written)
      header_written = output.write(pcapng_header("tiltgate " TILTGATE_VERSION, o.port));
    return header_written && output.write(pcapng_packet(frame, format));
  });
}

}  // namespace

Subcommand add_capture(CLI::App& app, FamilyList families) {
  auto options = std::make_shared<CaptureOptions>();
  CLI::App* command = app.add_subcommand(
      "capture", "write what a line carries as a pcapng file for Wireshark: through the running "
                 "gateway (--bus), or listening only (--port)");
  command->add_option("--bus", options->bus, "the gateway's bus to capture")
      ->group("Through the running gateway");
  command->add_option("-c,--config", options->config,
                      "the gateway's configuration, where its control socket is named")
      ->group("Through the running gateway");
  command
      ->add_option("--control-socket", options->control_socket,
                   fmt::format("the gateway's control socket (default: the configuration's "
                               "[server] control_socket, else {})",
                               kDefaultControlSocket))
      ->group("Through the running gateway");
  command->add_flag("--last", options->last,
                    "the bus's black box: the frames of its last black_box_s seconds")
      ->group("Through the running gateway");
  command->add_option("--port", options->port,
                      "listen only on this tty, on a line another master drives")
      ->group("Listening only");
  command->add_option("--protocol", options->protocol, "the line's protocol")
      ->group("Listening only");
  command->add_option("--baud", options->baud, "the line's rate")->group("Listening only");
  command->add_option("--parity", options->parity,
                      "even, odd or none, where the protocol lets the bus choose")
      ->group("Listening only");
  command->add_option("--stop-bits", options->stop_bits, "1 or 2, where the protocol lets the bus choose")
      ->group("Listening only");
  command->add_option("--seconds", options->seconds,
                      "capture this long (default 0: until Ctrl-C)")
      ->check(CLI::Range(std::int64_t{0}, std::int64_t{86'400}));
  command->add_option("-o,--output", options->output, "the pcapng file, or - for stdout")
      ->required();
  return {command, [options, families]() -> int {
            const CaptureOptions& o = *options;
            const bool through = !o.bus.empty();
            const bool listening = !o.port.empty();
            if (through == listening)
              return usage_error("give --bus (through the running gateway) or --port "
                                 "(listening only), one of them");
            if (through) {
              if (o.last && o.seconds > 0)
                return usage_error("--last writes the black box: no --seconds with it");
              return capture_through_gateway(o, families);
            }
            if (o.last) return usage_error("--last is a running gateway's: give --bus");
            if (o.protocol.empty()) return usage_error("--port needs --protocol");
            if (o.baud == 0) return usage_error("--port needs --baud");
            return capture_listening(o, families);
          }};
}

}  // namespace tiltgate
