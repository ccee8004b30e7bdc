#include "capture_cli/listen_capture.h"

#include <boost/asio/co_spawn.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/signal_set.hpp>
#include <boost/asio/steady_timer.hpp>
#include <algorithm>
#include <csignal>
#include <exception>
#include <iostream>
#include <optional>
#include <string>
#include <utility>

#include "capture/line_listener.h"
#include "driver/expected.h"
#include "driver/visible_text.h"

namespace tiltgate {
namespace {

// The bus's framing from --parity and --stop-bits, as a [[bus]]'s parity and stop_bits are read
// (config/bus_section.cpp): only where the protocol lets a bus choose; without parity two stop
// bits by default, so a character keeps its length (Modbus over Serial Line V1.02, 2.5.1).
Expected<Framing, std::string> listen_framing(const ListenCaptureOptions& options) {
  const ProtocolDescriptor& protocol = *options.protocol;
  const bool given = !options.parity.empty() || options.stop_bits != 0;
  if (!protocol.bus_chooses_framing) {
    if (given)
      return Unexpected("--parity and --stop-bits: " + std::string(protocol.name) +
                        " lines have a fixed framing");
    return protocol.framing;
  }
  if (!options.parity.empty() && options.parity != "even" && options.parity != "odd" &&
      options.parity != "none")
    return Unexpected("--parity " + options.parity + ": expected even, odd or none");
  if (options.stop_bits != 0 && options.stop_bits != 1 && options.stop_bits != 2)
    return Unexpected("--stop-bits " + std::to_string(options.stop_bits) + ": expected 1 or 2");
  const Framing fallback = protocol.framing;
  const bool none = options.parity.empty() ? fallback == Framing::eight_none_one ||
                                                 fallback == Framing::eight_none_two
                                           : options.parity == "none";
  const bool odd = options.parity.empty() ? fallback == Framing::eight_odd_one
                                          : options.parity == "odd";
  const int stops = options.stop_bits != 0 ? options.stop_bits : (none ? 2 : 1);
  if (!none && stops == 2)
    return Unexpected(std::string("--stop-bits 2 with parity is not supported: expected 1, or "
                                  "--parity none"));
  if (none) return stops == 2 ? Framing::eight_none_two : Framing::eight_none_one;
  return odd ? Framing::eight_odd_one : Framing::eight_even_one;
}

// What the options ask of the protocol, or why it refuses them (exit code 2).
Expected<LineListenerOptions, std::string> listen_options(const ListenCaptureOptions& options) {
  const ProtocolDescriptor& protocol = *options.protocol;
  if (protocol.passive_framer == nullptr) {
    if (protocol.devices_speak_tcp)
      return Unexpected("--protocol " + std::string(protocol.name) +
                        ": its devices speak TCP, there is no serial line to listen to");
    return Unexpected("--protocol " + std::string(protocol.name) + ": cannot be listened to");
  }
  if (!protocol.bauds.empty() &&
      std::find(protocol.bauds.begin(), protocol.bauds.end(), options.baud) == protocol.bauds.end())
    return Unexpected("--baud " + std::to_string(options.baud) + ": not a rate " +
                      std::string(protocol.name) + " lines run at");
  const auto framing = listen_framing(options);
  if (!framing) return Unexpected(framing.error());
  LineListenerOptions listening;
  listening.path = options.port;
  listening.baud = options.baud;
  listening.framing = *framing;
  listening.framer = protocol.passive_framer;
  return listening;
}

// Hands each frame on until the output refuses one; then stops the listener.
class ListenCaptureSink final : public HeardTrafficSink {
 public:
  explicit ListenCaptureSink(std::function<bool(const CapturedFrame&)> on_frame)
      : on_frame_(std::move(on_frame)) {}

  void listen_with(LineListener& listener) { listener_ = &listener; }
  bool refused() const { return refused_; }

  void on_frame(const HeardFrame& frame) override {
    if (refused_) return;
    if (on_frame_(frame.frame)) return;
    refused_ = true;
    if (listener_ != nullptr) listener_->stop();
  }
  void on_exchange(const HeardExchange&) override {}

 private:
  std::function<bool(const CapturedFrame&)> on_frame_;
  LineListener* listener_ = nullptr;
  bool refused_ = false;
};

// Nothing in the listener throws on purpose; should something escape it, it is said, not lost.
std::string listen_failure_text(const std::exception_ptr& error) {
  try {
    std::rethrow_exception(error);
  } catch (const std::exception& e) {
    return std::string("the listener failed: ") + e.what();
  } catch (...) {
    return "the listener failed";
  }
}

void print_listen_summary(const PassiveDecoderCounters& c) {
  std::cerr << "tiltgate capture: " << c.frames << " frames, " << c.requests << " requests, "
            << c.replies_paired << " replies paired, " << c.no_replies << " no reply, "
            << c.garbled << " garbled (" << c.garbled_bytes << " bytes), " << c.bad_checks
            << " bad checksums, " << c.unpaired_replies << " replies to no request\n";
}

}  // namespace

int run_listen_capture(const ListenCaptureOptions& options,
                       std::function<bool(const CapturedFrame&)> on_frame) {
  const auto listening = listen_options(options);
  if (!listening) {
    std::cerr << "tiltgate capture: " << listening.error() << "\n";
    return 2;
  }
  boost::asio::io_context io;
  ListenCaptureSink sink(std::move(on_frame));
  LineListener listener(io.get_executor(), *listening, sink);
  sink.listen_with(listener);
  const auto opened = listener.open();
  if (!opened) {
    std::cerr << "tiltgate capture: cannot listen on " << visible_text(options.port) << ": "
              << opened.error() << "\n";
    return 1;
  }

  boost::asio::signal_set signals(io, SIGINT, SIGTERM);
  signals.async_wait([&](const boost::system::error_code& ec, int) {
    if (!ec) listener.stop();
  });
  boost::asio::steady_timer timer(io);
  if (options.duration.count() > 0) {
    timer.expires_after(options.duration);
    timer.async_wait([&](const boost::system::error_code& ec) {
      if (!ec) listener.stop();
    });
  }
  std::optional<std::string> failure;
  boost::asio::co_spawn(io, listener.run(),
                        [&](std::exception_ptr error, std::optional<std::string> why) {
                          failure = std::move(why);
                          if (error) failure = listen_failure_text(error);
                          signals.cancel();
                          timer.cancel();
                        });
  io.run();

  print_listen_summary(listener.counters());
  if (failure) {
    std::cerr << "tiltgate capture: " << visible_text(options.port) << ": " << *failure << "\n";
    return 1;
  }
  return sink.refused() ? 1 : 0;
}

}  // namespace tiltgate
