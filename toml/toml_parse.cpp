#include "toml/toml_parse.h"

#include <fmt/format.h>

#include "toml/toml_reader.h"

namespace tiltgate::toml_input {

namespace {

// Walks a text, keeping the line and column of where it is.
class Cursor {
 public:
  explicit Cursor(std::string_view text) : text_(text) {}

  bool done() const { return at_ >= text_.size(); }
  char peek() const { return text_[at_]; }
  bool starts_with(std::string_view s) const { return text_.substr(at_, s.size()) == s; }
  Place place() const { return {line_, column_}; }
  void advance(std::size_t count = 1) {
    for (; count > 0 && !done(); --count, ++at_) {
      if (text_[at_] == '\n') {
        ++line_;
        column_ = 1;
      } else {
        ++column_;
      }
    }
  }
  // Past a string that starts here ("...", '...', """...""", '''...'''): escapes count only
  // in the basic ones. An unterminated one runs to the end; toml++ says what is wrong with it.
  void skip_string() {
    const char quote = peek();
    const std::string_view triple = quote == '"' ? "\"\"\"" : "'''";
    const bool multi_line = starts_with(triple);
    advance(multi_line ? 3 : 1);
    while (!done()) {
      if (quote == '"' && peek() == '\\') {
        advance(2);
      } else if (multi_line ? starts_with(triple) : peek() == quote) {
        advance(multi_line ? 3 : 1);
        return;
      } else if (!multi_line && peek() == '\n') {
        return;  // a single-line string ends at its line, closed or not
      } else {
        advance();
      }
    }
  }
  void skip_comment() {
    while (!done() && peek() != '\n') advance();
  }

 private:
  std::string_view text_;
  std::size_t at_ = 0;
  int line_ = 1;
  int column_ = 1;
};

bool ends_or_starts_a_key(char c) {
  return c == '=' || c == ',' || c == '{' || c == '}' || c == '[' || c == ']' || c == '\n';
}

}  // namespace

std::optional<DeepKey> find_deep_key(std::string_view text) {
  Cursor cursor(text);
  std::size_t dots = 0;
  std::optional<Place> run_start;  // the first character since the last delimiter
  while (!cursor.done()) {
    const char c = cursor.peek();
    if (c != ' ' && c != '\t' && c != '\r' && !ends_or_starts_a_key(c) && !run_start)
      run_start = cursor.place();
    if (c == '"' || c == '\'') {
      cursor.skip_string();
      continue;
    }
    if (c == '#') {
      cursor.skip_comment();
      continue;
    }
    if (ends_or_starts_a_key(c)) {
      dots = 0;
      run_start.reset();
    } else if (c == '.' && ++dots + 1 > kMaxKeyParts) {
      return DeepKey{run_start.value_or(cursor.place()), dots + 1};
    }
    cursor.advance();
  }
  return std::nullopt;
}

Expected<toml::table, ParseFailure> parse_toml(std::string_view text,
                                               std::string_view source_name) {
  if (const std::optional<DeepKey> deep = find_deep_key(text)) {
    return Unexpected{ParseFailure{
        deep->where, fmt::format("a key of more than {} dotted parts: nothing here nests that "
                                 "deep, and it is refused before it is parsed",
                                 kMaxKeyParts)}};
  }
  try {
    return toml::parse(text, source_name);
  } catch (const toml::parse_error& e) {
    return Unexpected{ParseFailure{place_of(e.source()), std::string(e.description())}};
  }
}

}  // namespace tiltgate::toml_input
