#include "sparkplug/host_state.h"

#include <charconv>
#include <optional>

namespace tiltgate::sparkplug {
namespace {

// A reader of one flat JSON object: strings, numbers, true, false and null as values.
class FlatJsonReader {
 public:
  explicit FlatJsonReader(std::string_view text) : text_(text) {}

  void skip_space() {
    while (at_ < text_.size() &&
           (text_[at_] == ' ' || text_[at_] == '\t' || text_[at_] == '\n' || text_[at_] == '\r')) {
      ++at_;
    }
  }
  bool take(char c) {
    skip_space();
    if (at_ < text_.size() && text_[at_] == c) {
      ++at_;
      return true;
    }
    return false;
  }
  bool at_end() {
    skip_space();
    return at_ == text_.size();
  }
  // A string's raw text between its quotes (escapes are kept, and only skipped over).
  std::optional<std::string_view> string() {
    if (!take('"')) return std::nullopt;
    const std::size_t start = at_;
    while (at_ < text_.size() && text_[at_] != '"') {
      if (static_cast<unsigned char>(text_[at_]) < 0x20) return std::nullopt;
      at_ += text_[at_] == '\\' ? 2 : 1;
    }
    if (at_ >= text_.size()) return std::nullopt;
    return text_.substr(start, at_++ - start);
  }
  // A value other than a string, as its text: a number, true, false or null.
  std::optional<std::string_view> scalar() {
    skip_space();
    const std::size_t start = at_;
    while (at_ < text_.size() &&
           std::string_view(",} \t\r\n").find(text_[at_]) == std::string_view::npos) {
      ++at_;
    }
    const std::string_view word = text_.substr(start, at_ - start);
    if (word.empty() || word.front() == '{' || word.front() == '[') return std::nullopt;
    return word;
  }
  bool next_is_string() {
    skip_space();
    return at_ < text_.size() && text_[at_] == '"';
  }

 private:
  std::string_view text_;
  std::size_t at_ = 0;
};

bool is_number(std::string_view word) {
  double d = 0;
  const auto [end, error] = std::from_chars(word.data(), word.data() + word.size(), d);
  return error == std::errc{} && end == word.data() + word.size();
}

}  // namespace

Expected<HostState, std::string> parse_host_state(std::string_view json) {
  if (json.size() > kMaxHostStateBytes) {
    return Unexpected("a STATE payload of " + std::to_string(json.size()) + " bytes");
  }
  FlatJsonReader reader(json);
  if (!reader.take('{')) return Unexpected(std::string("a STATE payload is a JSON object"));
  std::optional<bool> online;
  std::optional<std::uint64_t> timestamp;
  bool first = true;
  while (!reader.take('}')) {
    if (!first && !reader.take(',')) return Unexpected(std::string("expected ',' or '}'"));
    first = false;
    const auto key = reader.string();
    if (!key || !reader.take(':')) return Unexpected(std::string("expected \"key\": value"));
    if (reader.next_is_string()) {
      if (!reader.string()) return Unexpected(std::string("an unterminated string"));
      continue;
    }
    const auto word = reader.scalar();
    if (!word) return Unexpected("the value of \"" + std::string(*key) + "\" is not a scalar");
    if (*key == "online") {
      if (*word != "true" && *word != "false") {
        return Unexpected(std::string("\"online\" is not true or false"));
      }
      online = *word == "true";
    } else if (*key == "timestamp") {
      std::uint64_t ms = 0;
      const auto [end, error] = std::from_chars(word->data(), word->data() + word->size(), ms);
      if (error != std::errc{} || end != word->data() + word->size()) {
        return Unexpected(std::string("\"timestamp\" is not a non-negative integer"));
      }
      timestamp = ms;
    } else if (*word != "true" && *word != "false" && *word != "null" && !is_number(*word)) {
      return Unexpected("the value of \"" + std::string(*key) + "\" is not JSON");
    }
  }
  if (!reader.at_end()) return Unexpected(std::string("text after the JSON object"));
  if (!online) return Unexpected(std::string("no \"online\" key"));
  if (!timestamp) return Unexpected(std::string("no \"timestamp\" key"));
  return HostState{*online, *timestamp};
}

}  // namespace tiltgate::sparkplug
