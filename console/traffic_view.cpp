#include "console/traffic_view.h"

#include <algorithm>
#include <ctime>

#include <fmt/format.h>

#include "capture/frame_json.h"

namespace tiltgate {

using json = nlohmann::json;

TrafficSlice take_traffic(const BlackBox& box, std::optional<std::uint64_t> after,
                          std::size_t limit) {
  TrafficSlice taken;
  taken.keep = box.keep();
  const std::uint64_t newest = box.newest();
  const bool starts = !after || *after > newest;
  const std::uint64_t recent = std::min(limit, kTrafficRecent);
  const std::uint64_t from = starts ? (newest > recent ? newest - recent : 0) : *after;
  taken.slice = box.since(from, limit);
  // A view that starts missed nothing: the frames before it were never its to show.
  if (starts) taken.slice.missed = 0;
  if (from > 0 && !taken.slice.frames.empty()) {
    BlackBox::Slice own = box.since(from - 1, 1);
    if (own.missed == 0 && own.frames.size() == 1) taken.before = std::move(own.frames.front());
  }
  return taken;
}

namespace {

json text_or_null(const std::optional<std::string>& text) {
  return text ? json(*text) : json(nullptr);
}

}  // namespace

json traffic_json(const TrafficSlice& taken, FrameReaders readers) {
  const auto read_request = [&](const CapturedFrame& frame) -> std::optional<CarriedRequest> {
    if (readers.read_request == nullptr) return std::nullopt;
    return readers.read_request(frame.bytes);
  };
  // The request a reply answers: the last one the line sent before it, as far as the view
  // holds it. A request the protocol cannot read leaves its replies without one.
  std::optional<CarriedRequest> request;
  const CapturedFrame* request_frame = nullptr;
  if (taken.before && taken.before->direction == FrameDirection::to_devices) {
    request = read_request(*taken.before);
    request_frame = &*taken.before;
  }
  const auto& frames = taken.slice.frames;
  // Numbers are consecutive and the last one is `next` (BlackBox::since).
  std::uint64_t number = taken.slice.next + 1 - frames.size();
  json list = json::array();
  for (const CapturedFrame& frame : frames) {
    json item = frame_json(frame);
    item["n"] = number++;
    std::optional<std::string> refusal;
    std::optional<std::string> values;
    if (frame.direction == FrameDirection::to_devices) {
      request = read_request(frame);
      request_frame = &frame;
    } else {
      if (readers.read_refusal != nullptr) refusal = readers.read_refusal(frame.bytes);
      if (readers.read_reply != nullptr && request_frame != nullptr)
        values = readers.read_reply(request_frame->bytes, frame.bytes);
    }
    item["address"] = request ? json(request->address) : json(nullptr);
    item["function"] = request ? json(request->function) : json(nullptr);
    item["refusal"] = text_or_null(refusal);
    item["values"] = text_or_null(values);
    list.push_back(std::move(item));
  }
  return json{{"frames", std::move(list)},
              {"next", taken.slice.next},
              {"missed", taken.slice.missed},
              {"keep_s", taken.keep.count()}};
}

std::string capture_file_name(std::string_view bus, std::chrono::system_clock::time_point now) {
  std::string name;
  for (const char c : bus) {
    const bool plain = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') ||
                       (c >= '0' && c <= '9') || c == '-' || c == '_' || c == '.';
    name += plain ? c : '_';
  }
  const std::time_t seconds = std::chrono::system_clock::to_time_t(now);
  std::tm local{};
  localtime_r(&seconds, &local);
  return fmt::format("tiltgate-{}-{:04}{:02}{:02}-{:02}{:02}{:02}.pcapng", name,
                     local.tm_year + 1900, local.tm_mon + 1, local.tm_mday, local.tm_hour,
                     local.tm_min, local.tm_sec);
}

}  // namespace tiltgate
