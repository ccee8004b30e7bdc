// `tiltgate watch` on the command line: the engine's rounds (commission/watch_engine.h) as one
// row per sensor, redrawn in place on a terminal, else plain lines; every reading appended to a
// CSV file with --log.
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fmt/format.h>
#include <fstream>
#include <iostream>
#include <unistd.h>

#include "commission_cli/commands.h"
#include "commission_cli/commission_run.h"
#include "commission/reading_format.h"
#include "commission/watch_engine.h"

namespace tiltgate {

namespace {

namespace asio = boost::asio;

// The command line's options beside the engine's.
struct WatchCommandOptions {
  WatchOptions watch;
  std::string log;  // CSV file every reading is appended to; empty: none
};

// The table, and a note per sensor where there is something to say (the model found, why it
// gives no reading): below the table when it is redrawn, else on stderr when a note changes.
class Display {
 public:
  explicit Display(bool redraw) : redraw_(redraw) {}

  void show(const std::vector<WatchRow>& rows, const std::vector<std::string>& notes) {
    if (redraw_) {
      // Back to the header drawn last time (ANSI cursor up), each line cleared as it is redrawn.
      if (drawn_ > 0) std::cout << fmt::format("\x1b[{}A", drawn_);
      std::cout << "\r\x1b[2K" << watch_header() << "\n";
      for (const WatchRow& row : rows) std::cout << "\r\x1b[2K" << watch_row(row) << "\n";
      int lines = int(rows.size()) + 1;
      for (const std::string& note : notes) {
        if (note.empty()) continue;
        std::cout << "\r\x1b[2K" << note << "\n";
        ++lines;
      }
      // Lines a longer note list left below are cleared.
      for (int i = lines; i < drawn_; ++i) std::cout << "\r\x1b[2K\n";
      drawn_ = std::max(drawn_, lines);
    } else {
      if (drawn_ == 0) std::cout << watch_header() << "\n";
      for (const WatchRow& row : rows) std::cout << watch_row(row) << "\n";
      drawn_ = 1;
      told_.resize(notes.size());
      for (std::size_t i = 0; i < notes.size(); ++i) {
        if (notes[i] == told_[i]) continue;
        if (!notes[i].empty()) std::cerr << "tiltgate watch: " << notes[i] << "\n";
        told_[i] = notes[i];
      }
    }
    std::cout.flush();
  }

 private:
  bool redraw_;
  int drawn_ = 0;
  std::vector<std::string> told_;  // the notes last written to stderr
};

// Appends to `path`, with the header when the file is new or empty.
Expected<std::ofstream, std::string> open_log(const std::string& path) {
  std::error_code ec;
  const bool is_new = !std::filesystem::exists(path, ec) || std::filesystem::file_size(path, ec) == 0;
  std::ofstream log(path, std::ios::app);
  if (!log) return Unexpected{fmt::format("--log: cannot open {}: {}", path, std::strerror(errno))};
  if (is_new) log << csv_header();
  log.flush();
  return log;
}

int watch_command(const BusOptions& bus_options, const WatchCommandOptions& options,
                  FamilyList families) {
  std::ofstream log;
  if (!options.log.empty()) {
    auto opened = open_log(options.log);
    if (!opened) {
      std::cerr << "tiltgate watch: " << opened.error() << "\n";
      return 2;
    }
    log = std::move(*opened);
  }
  Display display(options.watch.count == 0 && ::isatty(STDOUT_FILENO) == 1);
  const EventSink report = [&](const CommissionEvent& event) {
    if (const auto* reading = std::get_if<SensorReadingEvent>(&event); reading && log.is_open()) {
      log << csv_line(reading->polled, watch_row_of(*reading));
      log.flush();
    } else if (const auto* round = std::get_if<WatchRoundEvent>(&event)) {
      std::vector<WatchRow> rows;
      for (const SensorReadingEvent& r : round->readings) rows.push_back(watch_row_of(r));
      display.show(rows, round->notes);
    } else if (const auto* failed = std::get_if<FailedEvent>(&event)) {
      std::cerr << "tiltgate watch: " << failed->message << "\n";  // through a gateway
    }
  };
  return run_commissioning("watch", bus_options, families,
                           [&](CommissionBus& bus, const bool& stopping) -> asio::awaitable<int> {
                             co_return co_await watch_sensors(bus, options.watch, report,
                                                              stopping);
                           },
                           GatewayRequest{CommandRequest{"watch", bus_options, {}, {}, options.watch, {}},
                                          report, nullptr});
}

}  // namespace

Subcommand add_watch(CLI::App& app, FamilyList families, FamilyCommandsList commands) {
  auto bus = std::make_shared<BusOptions>();
  auto options = std::make_shared<WatchCommandOptions>();
  CLI::App* watch = app.add_subcommand("watch", "poll sensors in turn and show their angles, one "
                                                "row each (the Multi-Unit Angle Display)");
  add_bus_options(*watch, *bus, families);
  watch->add_option("--count", options->watch.count, "stop after this many rounds (plain lines)")
      ->check(CLI::Range(1, kMaxWatchRounds));
  watch->add_option("--interval", options->watch.interval_ms, "ms from one round to the next")
      ->check(CLI::Range(kMinWatchIntervalMs, kMaxWatchIntervalMs))
      ->capture_default_str();
  watch->add_option("--log", options->log,
                    "append every reading to this CSV file (time, address, serial, x_deg, "
                    "y_deg, tilt_deg, status)");
  watch->footer(watch_help_footer(commands));
  return {watch, [bus, options, families] { return watch_command(*bus, *options, families); },
          true};
}

}  // namespace tiltgate
