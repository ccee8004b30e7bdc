// The console's traffic view of a bus (docs/web-console.md, "Traffic"): the frames its black box
// (capture/black_box.h) holds after the last one the page showed, taken on the buses' executor
// (take_traffic), and the JSON the page lists them from, made on the HTTP thread (traffic_json);
// and the name its pcapng download is saved under. Pure: no Asio, no clock of its own.
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "capture/black_box.h"
#include "driver/carried_request.h"

namespace tiltgate {

// A view that starts (no `after`) shows this many of the newest frames: a screenful, not the
// whole minute.
inline constexpr std::size_t kTrafficRecent = 100;
// The most frames one reply carries: the page asks again at once after a full one, so a view
// that fell behind (a pause, a slow phone) catches up without one reply of megabytes.
inline constexpr std::size_t kTrafficLimit = 300;

struct TrafficSlice {
  BlackBox::Slice slice;
  // The frame numbered `after` itself, when still held: the request of a reply that comes first
  // in `slice` (the page polls every half second, so a request and its reply often straddle
  // two replies).
  std::optional<CapturedFrame> before;
  std::chrono::seconds keep{0};
};

// The frames after frame number `after`, at most `limit`. None, or a number the box has not
// reached (its bus was made anew by a reload, or the gateway restarted): the newest
// kTrafficRecent, with nothing counted as missed.
TrafficSlice take_traffic(const BlackBox& box, std::optional<std::uint64_t> after,
                          std::size_t limit = kTrafficLimit);

// How the bus's protocol reads a frame (ProtocolDescriptor::read_request, read_refusal,
// read_reply); null members read nothing.
struct FrameReaders {
  ReadRequest read_request = nullptr;
  ReadRefusal read_refusal = nullptr;
  ReadReply read_reply = nullptr;
};

// {"frames": [{frame_json's fields, "n", "address", "function", "refusal", "values"}],
//  "next", "missed", "keep_s"}: a request's address and function as the protocol reads them; a
// reply's those of the request before it (null when none is held, or it cannot be read), its
// refusal ("nak 0x03"), null for any other reply, and what it says as the answer to that
// request ("x 1.25 deg, y -0.5 deg"), null when the protocol reads nothing of it.
nlohmann::json traffic_json(const TrafficSlice& taken, FrameReaders readers);

// "tiltgate-BUS-20261202-051022.pcapng", `now` in local time; a character of the bus's name
// that a file name or the Content-Disposition header would not take as it is becomes '_'.
std::string capture_file_name(std::string_view bus, std::chrono::system_clock::time_point now);

}  // namespace tiltgate
