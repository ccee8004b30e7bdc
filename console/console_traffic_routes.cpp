// The web console's traffic routes of a bus (admin: frames carry settings): the frames its line
// carried, from its black box, as the page's live list (GET /api/buses/NAME/frames?after=N), and
// the whole black box as a pcapng file Wireshark opens (GET /api/buses/NAME/capture.pcapng)
// (docs/web-console.md, "Traffic").
//
// The audit trail gets one record per download, and one per view started (a request without
// `after`), never one per poll: a page polls twice a second. A refused request is one record
// too, as every admin route's is.
#include <charconv>

#include <boost/asio/co_spawn.hpp>
#include <boost/asio/use_awaitable.hpp>
#include <fmt/format.h>

#include "capture/pcapng.h"
#include "console/console_handler.h"
#include "console/console_reply.h"
#include "console/request_guard.h"
#include "console/traffic_view.h"
#include "gateway/gateway.h"

namespace tiltgate {

namespace asio = boost::asio;
using json = nlohmann::json;

namespace {

// What a route takes of a bus on the buses' executor, where its black box is recorded into;
// the JSON and the file are made from it on the HTTP thread.
struct BusTraffic {
  bool served = false;
  std::string protocol;
  std::chrono::seconds keep{0};
  TrafficSlice view;                  // the frames route's
  std::vector<CapturedFrame> held;    // the download's
};

// `after`'s value: none when absent; false when it is no frame number.
bool read_after(std::string_view target, std::optional<std::uint64_t>& after) {
  const std::string text = query_value(target, "after");
  if (text.empty()) return true;
  std::uint64_t number = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), number);
  if (error != std::errc() || end != text.data() + text.size()) return false;
  after = number;
  return true;
}

}  // namespace

asio::awaitable<HttpReply> ConsoleHandler::traffic_route(const HttpRequest& request,
                                                         std::string_view path,
                                                         const ConsoleSession& session) {
  const bool download = path.ends_with(kCaptureSuffix);
  const std::string_view suffix = download ? kCaptureSuffix : kFramesSuffix;
  const auto bus =
      path_name(path.substr(kBusPrefix.size(), path.size() - kBusPrefix.size() - suffix.size()));
  if (!bus) co_return error_reply(404, "no such bus");
  if (request.method != "GET") co_return error_reply(405, "GET only");
  const std::string setting = download ? "capture" : "traffic";
  if (!role_allows(session.role, Role::admin)) {
    const std::string why = download ? "a capture is for the admin role"
                                     : "the traffic view is for the admin role";
    record(session, *bus, setting, "", download ? "download" : "watch", "refused: " + why);
    co_return error_reply(403, why);
  }
  std::optional<std::uint64_t> after;
  if (!read_after(request.target, after))
    co_return error_reply(400, "after must be a frame number (the \"next\" of the last reply)");
  // Named, not a temporary in the co_await: g++ 12 destroys such a temporary twice.
  auto take = [&]() -> asio::awaitable<BusTraffic> {
    BusTraffic taken;
    if (context_.gateway == nullptr) co_return taken;
    const std::shared_ptr<BlackBox> box = context_.gateway->black_box(*bus);
    if (!box) co_return taken;
    for (const BusConfig& config : context_.gateway->config().buses)
      if (config.name == *bus) taken.protocol = config.protocol;
    taken.served = true;
    taken.keep = box->keep();
    if (download)
      taken.held = box->held();
    else
      taken.view = take_traffic(*box, after);
    co_return taken;
  };
  const BusTraffic taken =
      co_await asio::co_spawn(context_.gateway_executor, std::move(take), asio::use_awaitable);
  if (!taken.served) co_return error_reply(404, "no such bus");
  const ProtocolDescriptor* protocol = find_protocol(context_.families, taken.protocol).protocol;
  if (download) {
    const PcapngFormat format = protocol ? pcapng_format_of(*protocol) : PcapngFormat{};
    std::string file = pcapng_header("tiltgate", *bus);
    for (const CapturedFrame& frame : taken.held) file += pcapng_packet(frame, format);
    record(session, *bus, setting, "", fmt::format("last {} s", taken.keep.count()), "ok");
    HttpReply reply{200, "application/octet-stream", std::move(file)};
    reply.content_disposition = fmt::format(
        "attachment; filename=\"{}\"",
        capture_file_name(*bus, std::chrono::system_clock::now()));
    co_return reply;
  }
  if (!after) record(session, *bus, setting, "", "watch", "ok");
  json body = traffic_json(taken.view, protocol ? FrameReaders{protocol->read_request,
                                                               protocol->read_refusal,
                                                               protocol->read_reply}
                                                : FrameReaders{});
  body["bus"] = *bus;
  body["protocol"] = taken.protocol;
  co_return json_reply(200, body);
}

}  // namespace tiltgate
