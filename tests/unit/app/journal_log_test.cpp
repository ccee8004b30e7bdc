// Log lines for the journal: the syslog priority prefix journald reads, and when stderr is the
// journal's stream.
#include <doctest/doctest.h>

#include <spdlog/details/log_msg.h>

#include "app/journal_log.h"

using namespace tiltgate;

namespace {

std::string formatted(spdlog::level::level_enum level, std::string_view text) {
  const spdlog::details::log_msg message("tiltgate", level, text);
  spdlog::memory_buf_t line;
  journal_formatter()->format(message, line);
  return std::string(line.data(), line.size());
}

}  // namespace

TEST_CASE("journal: spdlog levels map to syslog priorities") {
  CHECK(syslog_priority(spdlog::level::critical) == 2);
  CHECK(syslog_priority(spdlog::level::err) == 3);
  CHECK(syslog_priority(spdlog::level::warn) == 4);
  CHECK(syslog_priority(spdlog::level::info) == 6);
  CHECK(syslog_priority(spdlog::level::debug) == 7);
  CHECK(syslog_priority(spdlog::level::trace) == 7);
}

TEST_CASE("journal: a line is its priority prefix and the message, without a timestamp") {
  CHECK(formatted(spdlog::level::warn, "bus line1: /dev/ttyUSB0 gone") ==
        "<4>bus line1: /dev/ttyUSB0 gone\n");
  CHECK(formatted(spdlog::level::err, "reload refused") == "<3>reload refused\n");
  CHECK(formatted(spdlog::level::info, "serving") == "<6>serving\n");
}

TEST_CASE("journal: JOURNAL_STREAM must name stderr's own device and inode") {
  CHECK(journal_stream_is("8:12345", 8, 12345));
  CHECK_FALSE(journal_stream_is("8:12345", 8, 12346));
  CHECK_FALSE(journal_stream_is("9:12345", 8, 12345));
  CHECK_FALSE(journal_stream_is("", 8, 12345));
  CHECK_FALSE(journal_stream_is("8:", 8, 0));
  CHECK_FALSE(journal_stream_is("8:12345x", 8, 12345));
  CHECK_FALSE(journal_stream_is("812345", 8, 12345));
}
