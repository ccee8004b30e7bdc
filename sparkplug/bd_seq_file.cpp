#include "sparkplug/bd_seq_file.h"

#include <charconv>
#include <string_view>
#include <system_error>

#include "store/file_io.h"

namespace tiltgate::sparkplug {

Expected<std::optional<std::uint8_t>, std::string> read_bd_seq(const std::filesystem::path& file) {
  std::error_code ec;
  if (!std::filesystem::exists(file, ec) && !ec) return std::optional<std::uint8_t>{};
  auto bytes = store::read_whole(file);
  if (!bytes) return Unexpected(bytes.error());
  std::string_view text(reinterpret_cast<const char*>(bytes->data()), bytes->size());
  while (!text.empty() && (text.back() == '\n' || text.back() == ' ')) text.remove_suffix(1);
  unsigned value = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (text.empty() || error != std::errc{} || end != text.data() + text.size() || value > 255)
    return Unexpected(file.string() + ": \"" + std::string(text.substr(0, 16)) +
                      "\" is not a bdSeq, expected a number 0..255");
  return std::optional<std::uint8_t>(static_cast<std::uint8_t>(value));
}

Expected<Done, std::string> write_bd_seq(const std::filesystem::path& file, std::uint8_t bd_seq) {
  const std::string text = std::to_string(bd_seq) + "\n";
  return store::replace_file(
      file, std::span(reinterpret_cast<const std::uint8_t*>(text.data()), text.size()));
}

}  // namespace tiltgate::sparkplug
