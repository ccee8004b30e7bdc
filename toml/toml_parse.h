// A TOML text parsed into a table, or where and why not: the one way the configuration, map
// files, device profiles and `tiltgate set --config` parse TOML.
//
// Before toml++ sees the text, every key is checked for how many dotted parts it has
// (`a.b.c = 1`, `[a.b.c]`, `{ a.b = 1 }`): Debian 12's toml++ follows a dotted key recursively,
// and a key of some 40,000 parts overflows the stack and kills the process (check, run, a
// reload). Nothing of ours nests deeper than a few levels; a key of more than kMaxKeyParts parts
// is an error at its line. toml++ bounds arrays and inline tables itself (256 levels).
#pragma once

#include <string>
#include <string_view>
#include <toml++/toml.h>

#include "driver/expected.h"
#include "toml/error_list.h"

namespace tiltgate::toml_input {

inline constexpr std::size_t kMaxKeyParts = 64;

struct ParseFailure {
  Place where;
  std::string description;
};

Expected<toml::table, ParseFailure> parse_toml(std::string_view text, std::string_view source_name);

// Where a key of more than kMaxKeyParts dotted parts starts, and its parts; none when there is
// none. Reads only what can be a key: strings and comments are skipped, and the dots are counted
// between the characters that end a key or start one (= , { } [ ] and line ends), where no TOML
// value has more than two (a float's, a time's fraction).
struct DeepKey {
  Place where;
  std::size_t parts = 0;
};
std::optional<DeepKey> find_deep_key(std::string_view text);

}  // namespace tiltgate::toml_input
