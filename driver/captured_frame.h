// A frame as a line carried it, for the capture (capture/: the black box, a live capture, the
// pcapng file Wireshark reads). The line knows no protocol: a frame is a request it wrote, or a
// run of bytes it received that its framer took as a reply or rejected, or that came too late.
#pragma once

#include <chrono>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace tiltgate {

enum class FrameDirection : std::uint8_t {
  to_devices,    // the gateway's request (Wireshark: outbound, sent)
  from_devices,  // what the devices sent (inbound, received)
};

struct CapturedFrame {
  // When its first byte went out, or came in, on this machine's clock (UTC): a request's when
  // it was handed to the port's driver, a reply's when the port gave its first byte to the line.
  std::chrono::system_clock::time_point time{};
  FrameDirection direction = FrameDirection::to_devices;
  std::vector<std::uint8_t> bytes;
  // Leading bytes sent with the 9th bit set (a 9-bit bus's address bytes); 0 elsewhere.
  std::uint8_t address_bytes = 0;
  // What the line made of it, in a few words: "request", "reply, CRC ok", "no reply: bad CRC",
  // "skipped", "late: after its time-out", "collision: the echo differs".
  std::string verdict;
};

// A frame as a line hands it over: views of the line's own buffers, valid during the call only,
// so recording a frame copies its bytes once, into the recorder's store.
struct FrameView {
  std::chrono::system_clock::time_point time{};
  FrameDirection direction = FrameDirection::to_devices;
  std::span<const std::uint8_t> bytes;
  std::uint8_t address_bytes = 0;
  std::string_view verdict;
};

// Where a line puts each frame it carries (capture/black_box.h). Called on the line's
// executor, in the order the frames were on the wire; must not block.
class FrameRecorder {
 public:
  virtual ~FrameRecorder() = default;
  virtual void record(const FrameView& frame) = 0;
  // How long it keeps what it was given, for the log line of a sensor that stops answering.
  virtual std::chrono::seconds keep() const = 0;
};

}  // namespace tiltgate
