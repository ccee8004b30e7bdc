// Captures what the process's default logger writes, at a chosen level, for tests that check
// log lines ("LEVEL message" per line). Restores the previous default logger when it goes.
#pragma once

#include <spdlog/sinks/ostream_sink.h>
#include <spdlog/spdlog.h>

#include <memory>
#include <sstream>
#include <string>
#include <vector>

namespace tiltgate::test {

class CapturedLog {
 public:
  explicit CapturedLog(spdlog::level::level_enum level)
      : previous_(spdlog::default_logger()),
        previous_level_(previous_->level()),
        logger_(std::make_shared<spdlog::logger>(
            "captured", std::make_shared<spdlog::sinks::ostream_sink_st>(text_))) {
    logger_->set_pattern("%l %v");
    logger_->set_level(level);
    spdlog::set_default_logger(logger_);
  }
  ~CapturedLog() {
    spdlog::set_default_logger(previous_);
    previous_->set_level(previous_level_);
  }
  CapturedLog(const CapturedLog&) = delete;
  CapturedLog& operator=(const CapturedLog&) = delete;

  std::vector<std::string> lines() const {
    std::vector<std::string> out;
    std::istringstream in(text_.str());
    for (std::string line; std::getline(in, line);) out.push_back(line);
    return out;
  }
  // The lines that start with `prefix`.
  std::vector<std::string> starting_with(const std::string& prefix) const {
    std::vector<std::string> out;
    for (const std::string& line : lines()) {
      if (line.rfind(prefix, 0) == 0) out.push_back(line);
    }
    return out;
  }

 private:
  std::ostringstream text_;
  std::shared_ptr<spdlog::logger> previous_;
  spdlog::level::level_enum previous_level_;
  std::shared_ptr<spdlog::logger> logger_;
};

}  // namespace tiltgate::test
