// Tell the Line when the reply to one Dyna request has arrived, one framer per protocol.
// Header-only: driver/line.h brings in an Asio header, which the pure codec library must not
// include, so these thin adapters stay outside it and the logic stays in the parsers.
#pragma once

#include <optional>
#include <string>

#include "driver/line.h"
#include "spectron/ascii_frame_parser.h"
#include "spectron/nine_bit_codec.h"

namespace tiltgate::spectron {

// 9-bit addressing: the first line up to CR LF (replies carry no address; only the addressed
// module answers). Noise bytes and overlong lines are dropped by NineBitLineParser. Nothing in a
// line says which request it answers: a late one is kept out by the Line's quiet guard after a
// time-out (driver/line.h), not here.
class NineBitReplyFramer : public ReplyFramer {
 public:
  void reset() override {
    parser_.reset();
    reply_.reset();
    overlong_before_ = parser_.counters().overlong_lines;
  }

  bool feed(std::span<const std::uint8_t> bytes) override {
    if (!reply_) {
      parser_.feed(bytes);
      reply_ = parser_.next();
    }
    return reply_.has_value();
  }

  // The reply line without its CR LF.
  const std::optional<std::string>& reply() const { return reply_; }
  const LineParserCounters& counters() const { return parser_.counters(); }

  // The protocol has no checksum: a reply is whole when its CR LF arrives.
  FramerReport report() const override {
    FramerReport report;
    if (reply_) {
      report.reply.assign(reply_->begin(), reply_->end());
      report.reply.push_back('\r');
      report.reply.push_back('\n');
    }
    report.reply_verdict = "CR LF, no checksum";
    if (parser_.counters().overlong_lines > overlong_before_) {
      report.rejected_verdict = "overlong line";
    }
    return report;
  }

 private:
  NineBitLineParser parser_;
  std::optional<std::string> reply_;
  std::uint64_t overlong_before_ = 0;  // the parser's count at reset()
};

// Modbus-ASCII: the first good frame from the addressed module answering the request's
// command. Other frames (a late reply to an earlier request, another module) are skipped;
// bad LRCs are counted.
class AsciiReplyFramer : public ReplyFramer {
 public:
  explicit AsciiReplyFramer(AsciiFrame request) : request_(std::move(request)) {}

  void reset() override {
    parser_.reset();
    reply_.reset();
    reply_text_.clear();
    counters_before_ = parser_.counters();
  }

  bool feed(std::span<const std::uint8_t> bytes) override {
    if (reply_) return true;
    parser_.feed(bytes);
    while (auto frame = parser_.next()) {
      if (is_reply_to(*frame, request_)) {
        reply_ = std::move(*frame);
        reply_text_ = parser_.last_text();
        break;
      }
    }
    return reply_.has_value();
  }

  const std::optional<AsciiFrame>& reply() const { return reply_; }
  std::uint64_t lrc_errors() const { return parser_.counters().lrc_errors; }
  const AsciiParserCounters& counters() const { return parser_.counters(); }

  FramerReport report() const override {
    FramerReport report;
    report.reply.assign(reply_text_.begin(), reply_text_.end());
    report.reply_verdict = "LRC ok";
    const AsciiParserCounters& now = parser_.counters();
    if (now.lrc_errors > counters_before_.lrc_errors) {
      report.rejected_verdict = "bad LRC";
    } else if (now.malformed > counters_before_.malformed) {
      report.rejected_verdict = "malformed frame";
    }
    return report;
  }

 private:
  AsciiFrame request_;
  AsciiFrameParser parser_;
  std::optional<AsciiFrame> reply_;
  std::string reply_text_;              // the reply's characters as received
  AsciiParserCounters counters_before_;  // the parser's counts at reset()
};

}  // namespace tiltgate::spectron
