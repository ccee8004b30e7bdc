#include "control/capture_runner.h"

#include <boost/asio/redirect_error.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/asio/this_coro.hpp>
#include <boost/asio/use_awaitable.hpp>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "audit/audit_trail.h"
#include "capture/frame_json.h"
#include "control/carried_change.h"

namespace tiltgate {

namespace asio = boost::asio;
using json = nlohmann::json;

namespace {

// How often a live capture looks into the black box: its frames reach the command this late
// at most, and the black box keeps them far longer than this meanwhile.
constexpr std::chrono::milliseconds kLiveLook{100};
// The most a live capture sends of one look; the rest follows at the next.
constexpr std::size_t kFramesPerLook = 2000;
// The longest live capture asked for by time.
constexpr std::int64_t kMaxSeconds = 86'400;

void emit_error(const std::function<void(std::string)>& emit, const std::string& message) {
  emit(json{{"event", "error"}, {"message", message}}.dump());
}

void emit_frame(const std::function<void(std::string)>& emit, const CapturedFrame& frame) {
  json event = frame_json(frame);
  event["event"] = "frame";
  emit(event.dump());
}

void record_capture(const ServedBus& bus, const WriteOrigin& by, std::string what) {
  AuditTrail* trail = bus.scheduler ? bus.scheduler->audit() : nullptr;
  if (trail == nullptr) return;
  trail->record(AuditRecord{control::now_unix_ms(), by, bus.config.name, "capture", "",
                            std::move(what), "ok"});
}

asio::awaitable<int> run_capture(json asked, ServedBus bus, WriteOrigin by,
                                 std::function<void(std::string)> emit, CommandStop& stop) {
  const bool last = asked.value("last", false);
  const json seconds_value = asked.value("seconds", json(0));
  if (!seconds_value.is_number_integer() || seconds_value.get<std::int64_t>() < 0 ||
      seconds_value.get<std::int64_t>() > kMaxSeconds) {
    emit_error(emit, fmt::format("seconds must be 0..{}", kMaxSeconds));
    co_return 2;
  }
  const auto seconds = std::chrono::seconds(seconds_value.get<std::int64_t>());
  const std::shared_ptr<BlackBox> box = bus.black_box;
  if (!box) {
    emit_error(emit, fmt::format("bus {} keeps no black box", bus.config.name));
    co_return 1;
  }
  emit(json{{"event", "capture"},
            {"bus", bus.config.name},
            {"protocol", bus.config.protocol},
            {"dissector", bus.protocol ? std::string(bus.protocol->wireshark_dissector) : ""},
            {"keep_s", box->keep().count()}}
           .dump());
  if (last) {
    record_capture(bus, by, fmt::format("last {} s", box->keep().count()));
    for (const CapturedFrame& frame : box->held()) emit_frame(emit, frame);
    co_return 0;
  }
  record_capture(bus, by, seconds.count() > 0 ? fmt::format("live {} s", seconds.count())
                                              : std::string("live until stopped"));
  asio::steady_timer timer(co_await asio::this_coro::executor);
  stop.on_request = [&timer] { timer.cancel(); };
  const auto end = std::chrono::steady_clock::now() + seconds;
  std::uint64_t next = box->newest();
  while (!stop.requested) {
    const auto now = std::chrono::steady_clock::now();
    if (seconds.count() > 0 && now >= end) break;
    timer.expires_at(seconds.count() > 0 ? std::min(now + kLiveLook, end) : now + kLiveLook);
    boost::system::error_code ec;
    co_await timer.async_wait(asio::redirect_error(asio::use_awaitable, ec));
    for (;;) {
      BlackBox::Slice slice = box->since(next, kFramesPerLook);
      if (slice.missed > 0) emit(json{{"event", "missed"}, {"frames", slice.missed}}.dump());
      for (const CapturedFrame& frame : slice.frames) emit_frame(emit, frame);
      next = slice.next;
      if (slice.frames.size() < kFramesPerLook || stop.requested) break;
    }
  }
  stop.on_request = nullptr;
  co_return 0;
}

}  // namespace

bool is_capture_request(const std::string& request) {
  const json asked = json::parse(request, nullptr, false);
  return asked.is_object() && asked.value("command", std::string()) == "capture";
}

CommandRunner with_capture(CommandRunner commissioning) {
  return [commissioning = std::move(commissioning)](
             std::string request, ServedBus bus, WriteOrigin by,
             std::function<void(std::string)> emit, CommandStop& stop) -> asio::awaitable<int> {
    if (!is_capture_request(request))
      co_return co_await commissioning(std::move(request), std::move(bus), std::move(by),
                                       std::move(emit), stop);
    co_return co_await run_capture(json::parse(request), std::move(bus), std::move(by),
                                   std::move(emit), stop);
  };
}

}  // namespace tiltgate
