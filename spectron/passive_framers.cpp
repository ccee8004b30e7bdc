#include "spectron/passive_framers.h"

#include <optional>
#include <string_view>

#include "spectron/ascii_codec.h"
#include "spectron/assumptions.h"
#include "spectron/nine_bit_codec.h"

namespace tiltgate::spectron {
namespace {

constexpr std::string_view kNoChecksum = "CR LF, no checksum";

bool passive_is_hex(std::uint8_t c) {
  return (c >= '0' && c <= '9') || (c >= 'A' && c <= 'F') || (c >= 'a' && c <= 'f');
}

// Printable ASCII and tab: what a 9-bit line may hold (A5).
bool passive_is_text(std::uint8_t c) { return (c >= 0x20 && c <= 0x7E) || c == '\t'; }

std::string_view passive_text(std::span<const std::uint8_t> bytes) {
  return {reinterpret_cast<const char*>(bytes.data()), bytes.size()};
}

// Where a line of text starting at `from` ends (one past its LF), every character before its
// CR LF accepted by `fits` and at most `longest` of them: the end; need_more while it may yet
// end; not_a_start once it cannot.
struct PassiveLineEnd {
  PassiveCut::Kind kind = PassiveCut::Kind::need_more;
  std::size_t end = 0;
};
template <class Fits>
PassiveLineEnd passive_line_end(std::span<const std::uint8_t> heard, std::size_t from,
                                std::size_t longest, Fits fits) {
  for (std::size_t i = from; i < heard.size(); ++i) {
    const std::uint8_t c = heard[i];
    if (i > from && heard[i - 1] == '\r')
      return c == '\n' ? PassiveLineEnd{PassiveCut::Kind::frame, i + 1}
                       : PassiveLineEnd{PassiveCut::Kind::not_a_start, 0};
    if (c == '\r') continue;
    if (!fits(c) || i - from >= longest) return PassiveLineEnd{PassiveCut::Kind::not_a_start, 0};
  }
  return {};
}

// Whether `line` (without its CR LF) can answer the 9-bit request `request` (address byte,
// body, CR LF): reads answer one number, the firmware request some text, the rest any line.
bool passive_nine_bit_answers(std::string_view line, std::span<const std::uint8_t> request) {
  if (request.size() < 4) return true;
  const auto asked = parse_nine_bit_body(passive_text(request.subspan(1, request.size() - 3)));
  if (!asked) return true;  // a request heard garbled: any line may be its reply
  switch (asked->command) {
    case NineBitCommand::read_eeprom:
    case NineBitCommand::read_sensor:
    case NineBitCommand::read_temperature:
      return parse_nine_bit_number(line).has_value();
    case NineBitCommand::firmware: return parse_nine_bit_firmware(line).has_value();
    case NineBitCommand::reset:
    case NineBitCommand::write_eeprom: return true;
  }
  return true;
}

}  // namespace

PassiveCut ascii_passive_frame(std::span<const std::uint8_t> heard, PassiveRole role,
                               std::span<const std::uint8_t> request) {
  if (heard.empty()) return PassiveCut::need_more();
  if (heard[0] != ':') return PassiveCut::not_a_start();
  // ':' and the characters up to CR LF: hex digits only, the whole at most kMaxFrameLength.
  const PassiveLineEnd line = passive_line_end(heard, 1, kMaxFrameLength - 3, passive_is_hex);
  if (line.kind != PassiveCut::Kind::frame) return PassiveCut::of(line.kind);
  const std::string_view text = passive_text(heard.first(line.end));
  const auto frame = decode(text);
  if (!frame) {
    const bool bad_lrc = frame.error() == AsciiDecodeError::bad_lrc;
    return PassiveCut::whole(line.end, false, bad_lrc ? "bad LRC" : "malformed frame");
  }
  if (role == PassiveRole::reply && !request.empty()) {
    const auto asked = decode(passive_text(request));
    if (asked && !is_reply_to(*frame, *asked)) return PassiveCut::not_a_start();
  }
  return PassiveCut::whole(line.end, true, "LRC ok");
}

PassiveCut nine_bit_passive_frame(std::span<const std::uint8_t> heard, PassiveRole role,
                                  std::span<const std::uint8_t> request) {
  if (role == PassiveRole::request) {
    // The address byte, whatever its value, then the body up to CR LF.
    if (heard.empty()) return PassiveCut::need_more();
    const PassiveLineEnd line = passive_line_end(heard, 1, kMaxLineLength, passive_is_text);
    if (line.kind != PassiveCut::Kind::frame) return PassiveCut::of(line.kind);
    const auto body = passive_text(heard.subspan(1, line.end - 3));
    if (!parse_nine_bit_body(body)) return PassiveCut::not_a_start();
    return PassiveCut::whole(line.end, true, kNoChecksum, kNineBitAddressBytes);
  }
  const PassiveLineEnd line = passive_line_end(heard, 0, kMaxLineLength, passive_is_text);
  if (line.kind != PassiveCut::Kind::frame) return PassiveCut::of(line.kind);
  if (!request.empty() &&
      !passive_nine_bit_answers(passive_text(heard.first(line.end - 2)), request))
    return PassiveCut::not_a_start();
  return PassiveCut::whole(line.end, true, kNoChecksum);
}

}  // namespace tiltgate::spectron
