#include "spectron/ascii_frame_parser.h"

#include <string_view>

namespace tiltgate::spectron {
namespace {

bool is_hex(char c) {
  return (c >= '0' && c <= '9') || (c >= 'A' && c <= 'F') || (c >= 'a' && c <= 'f');
}

}  // namespace

std::size_t AsciiFrameParser::feed(std::span<const std::uint8_t> bytes) {
  for (std::uint8_t byte : bytes) take(static_cast<char>(byte));
  return ready_.size();
}

std::optional<AsciiFrame> AsciiFrameParser::next() {
  if (ready_.empty()) return std::nullopt;
  AsciiFrame frame = std::move(ready_.front());
  ready_.pop_front();
  last_text_ = std::move(ready_text_.front());
  ready_text_.pop_front();
  return frame;
}

void AsciiFrameParser::reset() {
  counters_.bytes_discarded += size_;
  size_ = 0;
  ready_.clear();
  ready_text_.clear();
}

void AsciiFrameParser::take(char c) {
  if (c == ':') {
    if (size_ > 0) abandon();  // a new start marker: the partial frame was cut short
    buffer_[size_++] = c;
    return;
  }
  if (size_ == 0) {
    ++counters_.bytes_discarded;  // noise between frames
    return;
  }
  const bool after_cr = buffer_[size_ - 1] == '\r';
  const bool fits = after_cr ? c == '\n' : (is_hex(c) || c == '\r');
  if (!fits || size_ == buffer_.size()) {
    abandon();
    ++counters_.bytes_discarded;  // `c` itself
    return;
  }
  buffer_[size_++] = c;
  if (c == '\n') complete();
}

void AsciiFrameParser::complete() {
  const std::string_view text(buffer_.data(), size_);
  auto frame = decode(text);
  if (frame) {
    ready_.push_back(std::move(*frame));
    ready_text_.emplace_back(text);
    ++counters_.frames_ok;
  } else {
    if (frame.error() == AsciiDecodeError::bad_lrc) {
      ++counters_.lrc_errors;
    } else {
      ++counters_.malformed;
    }
    counters_.bytes_discarded += size_;
  }
  size_ = 0;
}

void AsciiFrameParser::abandon() {
  ++counters_.malformed;
  counters_.bytes_discarded += size_;
  size_ = 0;
}

}  // namespace tiltgate::spectron
