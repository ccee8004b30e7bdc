#include "app/journal_log.h"

#include <charconv>
#include <cstdlib>
#include <spdlog/details/log_msg.h>
#include <spdlog/pattern_formatter.h>
#include <sys/stat.h>
#include <unistd.h>

namespace tiltgate {

namespace {

// Reads one decimal number from the front of `text`, and drops it.
template <typename Number>
bool take_decimal(std::string_view& text, Number& number) {
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), number);
  if (ec != std::errc{} || end == text.data()) return false;
  text.remove_prefix(static_cast<std::size_t>(end - text.data()));
  return true;
}

// spdlog's pattern flag %* : "<PRIORITY>".
class SyslogPriorityFlag : public spdlog::custom_flag_formatter {
 public:
  void format(const spdlog::details::log_msg& msg, const std::tm&,
              spdlog::memory_buf_t& dest) override {
    const char prefix[] = {'<', static_cast<char>('0' + syslog_priority(msg.level)), '>'};
    dest.append(prefix, prefix + sizeof prefix);
  }
  std::unique_ptr<custom_flag_formatter> clone() const override {
    return std::make_unique<SyslogPriorityFlag>();
  }
};

}  // namespace

int syslog_priority(spdlog::level::level_enum level) {
  switch (level) {
    case spdlog::level::critical: return 2;
    case spdlog::level::err: return 3;
    case spdlog::level::warn: return 4;
    case spdlog::level::info: return 6;
    default: return 7;  // debug, trace
  }
}

bool journal_stream_is(std::string_view journal_stream, dev_t device, ino_t inode) {
  unsigned long long stream_device = 0;
  unsigned long long stream_inode = 0;
  std::string_view rest = journal_stream;
  if (!take_decimal(rest, stream_device) || rest.empty() || rest.front() != ':') return false;
  rest.remove_prefix(1);
  if (!take_decimal(rest, stream_inode) || !rest.empty()) return false;
  return stream_device == static_cast<unsigned long long>(device) &&
         stream_inode == static_cast<unsigned long long>(inode);
}

bool stderr_is_journal() {
  const char* journal_stream = std::getenv("JOURNAL_STREAM");
  struct stat status {};
  if (journal_stream == nullptr || fstat(STDERR_FILENO, &status) != 0) return false;
  return journal_stream_is(journal_stream, status.st_dev, status.st_ino);
}

std::unique_ptr<spdlog::formatter> journal_formatter() {
  auto formatter = std::make_unique<spdlog::pattern_formatter>();
  formatter->add_flag<SyslogPriorityFlag>('*').set_pattern("%*%v");
  return formatter;
}

}  // namespace tiltgate
