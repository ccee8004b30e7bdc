#include "capture/passive_decoder.h"

#include <algorithm>
#include <string>
#include <utility>

namespace tiltgate {
namespace {

// Bytes held without a decision past this are cut as if a silence followed: no protocol's
// frame is near it (the longest, 264 bytes), so only a framer that keeps asking for more would
// reach it.
constexpr std::size_t kPassiveHeldLimit = 4096;

// The Modbus serial line's frame gap, in characters (Serial Line 2.5.1.1).
constexpr double kPassiveGapCharacters = 3.5;
constexpr std::chrono::milliseconds kPassiveMinSilence{2};

}  // namespace

std::chrono::nanoseconds listen_silence(std::chrono::nanoseconds character_time) {
  const auto gap = std::chrono::duration_cast<std::chrono::nanoseconds>(
      character_time * kPassiveGapCharacters);
  return std::max<std::chrono::nanoseconds>(gap, kPassiveMinSilence);
}

std::chrono::steady_clock::time_point first_byte_time(
    std::chrono::steady_clock::time_point read_done, std::size_t count,
    std::chrono::nanoseconds character_time, std::chrono::steady_clock::time_point previous_last) {
  const auto estimate = read_done - std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                        character_time * static_cast<std::int64_t>(count));
  return std::max(estimate, previous_last);
}

PassiveDecoder::PassiveDecoder(PassiveDecoderOptions options, HeardTrafficSink& sink)
    : options_(options), silence_(listen_silence(options.character_time)), sink_(sink) {}

const PassiveDecoder::Reading* PassiveDecoder::Readings::first(bool intact) const {
  for (std::size_t i = 0; i < size; ++i)
    if (items[i].cut.kind == PassiveCut::Kind::frame && items[i].cut.intact == intact)
      return &items[i];
  return nullptr;
}

bool PassiveDecoder::Readings::waiting() const {
  for (std::size_t i = 0; i < size; ++i)
    if (items[i].cut.kind == PassiveCut::Kind::need_more) return true;
  return false;
}

void PassiveDecoder::heard(std::span<const std::uint8_t> bytes, Clock::time_point first_byte) {
  if (bytes.empty()) return;
  const bool holding = !bytes_.empty() || !garbled_.empty();
  if (holding && first_byte - last_byte_ > silence_) decide(true);
  for (std::size_t i = 0; i < bytes.size(); ++i) {
    bytes_.push_back(bytes[i]);
    times_.push_back(first_byte + std::chrono::duration_cast<Clock::duration>(
                                      options_.character_time * static_cast<std::int64_t>(i)));
  }
  last_byte_ = times_.back();
  decide(false);
}

void PassiveDecoder::advance(Clock::time_point now) {
  const bool holding = !bytes_.empty() || !garbled_.empty();
  if (holding && now - last_byte_ > silence_) decide(true);
  if (waiting_ && bytes_.empty() && now - waiting_->ended > options_.reply_window)
    resolve(std::nullopt);
}

std::optional<PassiveDecoder::Clock::time_point> PassiveDecoder::next_deadline() const {
  // One tick past each limit: a gap must be longer than it.
  std::optional<Clock::time_point> deadline;
  if (!bytes_.empty() || !garbled_.empty())
    deadline = last_byte_ + std::chrono::duration_cast<Clock::duration>(silence_) +
               Clock::duration(1);
  if (waiting_) {
    const auto window_end = waiting_->ended + options_.reply_window + Clock::duration(1);
    deadline = deadline ? std::min(*deadline, window_end) : window_end;
  }
  return deadline;
}

void PassiveDecoder::finish() {
  decide(true);
  if (!waiting_) return;
  Waiting cut = std::move(*waiting_);
  waiting_.reset();
  cut.request.frame.verdict += ", listening ended";
  ++counters_.frames;
  sink_.on_frame(cut.request);
  for (const HeardFrame& frame : cut.after) sink_.on_frame(frame);
}

PassiveDecoder::Readings PassiveDecoder::read_at(std::size_t offset) const {
  const auto heard = std::span<const std::uint8_t>(bytes_).subspan(offset);
  Readings readings;
  auto read = [&](PassiveRole role, bool answering) {
    const std::span<const std::uint8_t> request =
        answering ? std::span<const std::uint8_t>(waiting_->request.frame.bytes)
                  : std::span<const std::uint8_t>();
    PassiveCut cut = options_.framer(heard, role, request);
    // A frame must take some of the bytes heard, and no more: anything else is no frame.
    if (cut.kind == PassiveCut::Kind::frame && (cut.length == 0 || cut.length > heard.size()))
      cut = PassiveCut::not_a_start();
    readings.items[readings.size++] = {role, answering, cut};
  };
  if (waiting_) read(PassiveRole::reply, true);
  read(PassiveRole::request, false);
  read(PassiveRole::reply, false);
  return readings;
}

PassiveDecoder::Later PassiveDecoder::look_later(std::size_t limit) const {
  Later later;
  for (std::size_t offset = 1; offset < bytes_.size(); ++offset) {
    const Readings readings = read_at(offset);
    if (readings.first(true)) {
      later.good = offset;
      break;
    }
    if (offset < limit && readings.waiting()) later.waiting = true;
  }
  return later;
}

void PassiveDecoder::decide(bool ended) {
  while (!bytes_.empty()) {
    expire_waiting(times_.front());
    const bool end_here = ended || bytes_.size() > kPassiveHeldLimit;
    const Readings head = read_at(0);
    if (const Reading* good = head.first(true)) {
      take(*good);
      continue;
    }
    if (head.waiting() && !end_here) {
      if (look_later(0).good) {  // whole before the frame in front could be: noise
        drop(1);
        continue;
      }
      return;
    }
    if (const Reading* bad = head.first(false)) {
      if (!end_here) {
        const Later later = look_later(bad->cut.length);
        if (later.good && *later.good < bad->cut.length) {  // a good frame starts inside it
          drop(1);
          continue;
        }
        if (!later.good && later.waiting) return;  // one inside it may yet be good
      }
      take(*bad);
      continue;
    }
    if (head.waiting()) {  // a partial frame, cut short by the silence
      drop(bytes_.size());
      break;
    }
    drop(1);
  }
  if (ended) flush_garbled();
}

void PassiveDecoder::take(const Reading& reading) {
  flush_garbled();
  const std::size_t length = reading.cut.length;
  const HeardKind kind =
      reading.role == PassiveRole::request ? HeardKind::request : HeardKind::reply;
  HeardFrame frame = frame_at(kind, std::span(bytes_).first(length), times_.front());
  frame.intact = reading.cut.intact;
  frame.frame.address_bytes = reading.cut.address_bytes;
  const Clock::time_point last = times_[length - 1];
  bytes_.erase(bytes_.begin(), bytes_.begin() + static_cast<std::ptrdiff_t>(length));
  times_.erase(times_.begin(), times_.begin() + static_cast<std::ptrdiff_t>(length));
  if (!frame.intact) ++counters_.bad_checks;
  const std::string check(reading.cut.verdict);

  if (kind == HeardKind::request) {
    if (waiting_) resolve(std::nullopt);  // the master moved on: no reply came
    ++counters_.requests;
    frame.frame.verdict = "request, " + check;
    waiting_ = Waiting{std::move(frame), last, {}};
    return;
  }
  if (reading.answering) {
    ++counters_.replies_paired;
    frame.answers = waiting_->request.number;
    frame.frame.verdict = "reply, " + check;
    resolve(std::move(frame));
    return;
  }
  ++counters_.unpaired_replies;
  frame.frame.verdict = (waiting_ ? "reply to another request, " : "reply to no request heard, ") +
                        check;
  emit(std::move(frame));
}

void PassiveDecoder::drop(std::size_t count) {
  if (garbled_.empty()) garbled_time_ = times_.front();
  const auto end = static_cast<std::ptrdiff_t>(count);
  garbled_.insert(garbled_.end(), bytes_.begin(), bytes_.begin() + end);
  bytes_.erase(bytes_.begin(), bytes_.begin() + end);
  times_.erase(times_.begin(), times_.begin() + end);
}

void PassiveDecoder::flush_garbled() {
  if (garbled_.empty()) return;
  HeardFrame frame = frame_at(HeardKind::garbled, garbled_, garbled_time_);
  frame.frame.verdict = "garbled";
  ++counters_.garbled;
  counters_.garbled_bytes += garbled_.size();
  garbled_.clear();
  emit(std::move(frame));
}

void PassiveDecoder::expire_waiting(Clock::time_point at) {
  if (waiting_ && at - waiting_->ended > options_.reply_window) resolve(std::nullopt);
}

void PassiveDecoder::resolve(std::optional<HeardFrame> reply) {
  Waiting done = std::move(*waiting_);
  waiting_.reset();
  if (!reply) {
    ++counters_.no_replies;
    done.request.frame.verdict += ", no reply";
  }
  counters_.frames += 1 + (reply ? 1 : 0);
  sink_.on_frame(done.request);
  for (const HeardFrame& frame : done.after) sink_.on_frame(frame);
  if (reply) sink_.on_frame(*reply);
  sink_.on_exchange(HeardExchange{std::move(done.request), std::move(reply)});
}

void PassiveDecoder::emit(HeardFrame frame) {
  ++counters_.frames;
  if (waiting_) {
    waiting_->after.push_back(std::move(frame));
    return;
  }
  sink_.on_frame(frame);
}

HeardFrame PassiveDecoder::frame_at(HeardKind kind, std::span<const std::uint8_t> bytes,
                                    Clock::time_point first) {
  HeardFrame frame;
  frame.number = next_number_++;
  frame.kind = kind;
  frame.frame.time = options_.wall_anchor +
                     std::chrono::duration_cast<std::chrono::system_clock::duration>(
                         first - options_.steady_anchor);
  const bool from_devices = kind == HeardKind::reply || (kind == HeardKind::garbled && waiting_);
  frame.frame.direction = from_devices ? FrameDirection::from_devices : FrameDirection::to_devices;
  frame.frame.bytes.assign(bytes.begin(), bytes.end());
  return frame;
}

}  // namespace tiltgate
