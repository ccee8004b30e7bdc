// `tiltgate watch`: the vendor's Multi-Unit Angle Display. Polls each sensor in turn through
// its driver and shows one row per sensor: redrawn in place on a terminal, else plain lines.
#include <boost/asio/redirect_error.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/asio/this_coro.hpp>
#include <boost/asio/use_awaitable.hpp>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fmt/format.h>
#include <fstream>
#include <iostream>
#include <unistd.h>

#include "commission/commands.h"
#include "commission/commission_run.h"
#include "commission/model_detection.h"
#include "commission/reading_format.h"

namespace tiltgate {

namespace {

namespace asio = boost::asio;

struct WatchOptions {
  int count = 0;  // rounds before stopping; 0: until SIGINT/SIGTERM
  int interval_ms = 500;
  std::string log;  // CSV file every reading is appended to; empty: none
};

// The pause between rounds is waited out in slices, so a signal ends it promptly.
constexpr std::chrono::milliseconds kWaitSlice{50};

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

// What to tell of one sensor after a poll: why it gave no reading (an answer that is no reading;
// silence shows in the table), and the model found.
std::string note_for(const CommissionBus& bus, const CommissionedSensor& sensor,
                     const PollOutcome& outcome, const std::string& model_found) {
  if (outcome.result != PollResult::refused && outcome.result != PollResult::no_reading)
    return model_found;
  const std::string why = poll_outcome_message(bus, sensor, outcome);
  return model_found.empty() ? why : why + "; " + model_found;
}

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

asio::awaitable<void> pause_until(SteadyClock::time_point until, const bool& stopping) {
  asio::steady_timer timer(co_await asio::this_coro::executor);
  while (!stopping && SteadyClock::now() < until) {
    timer.expires_after(std::min<SteadyClock::duration>(kWaitSlice, until - SteadyClock::now()));
    boost::system::error_code ec;
    co_await timer.async_wait(asio::redirect_error(asio::use_awaitable, ec));
  }
}

int watch_command(const BusOptions& bus_options, const WatchOptions& options,
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
  const bool redraw = options.count == 0 && ::isatty(STDOUT_FILENO) == 1;
  return run_commissioning(
      "watch", bus_options, families,
      [&](CommissionBus& bus, const bool& stopping) -> asio::awaitable<int> {
        Display display(redraw);
        const std::size_t count = bus.sensors().size();
        std::vector<ReadingRate> rates(count);
        // A sensor's model is checked (or found) at its first poll that gets an answer.
        std::vector<bool> checked(count, false);
        std::vector<std::string> models_found(count), notes(count);
        const std::chrono::milliseconds interval(options.interval_ms);
        for (int round = 1; !stopping; ++round) {
          const SteadyClock::time_point round_start = SteadyClock::now();
          std::vector<WatchRow> rows;
          for (std::size_t i = 0; i < count && !stopping; ++i) {
            CommissionedSensor& sensor = bus.sensors()[i];
            PollOutcome outcome;
            if (!checked[i]) {
              const ModelCheck check = co_await check_model(bus, sensor, stopping);
              outcome = check.outcome();
              checked[i] = outcome.result != PollResult::silent;
              models_found[i] = model_check_message(sensor, check);
            } else {
              const PollMark before = mark_before_poll(sensor.driver->state());
              co_await sensor.driver->poll(bus.line());
              outcome = outcome_since(before, sensor.driver->state());
            }
            if (stopping) break;
            rates[i].update(sensor.driver->state());
            notes[i] = note_for(bus, sensor, outcome, models_found[i]);
            rows.push_back(snapshot_of(sensor.config.address, sensor.driver->state(),
                                       SteadyClock::now(), rates[i].per_second(),
                                       outcome.result));
            if (log.is_open() && !stopping) {
              log << csv_line(std::chrono::system_clock::now(), rows.back());
              log.flush();
            }
          }
          if (stopping) break;
          display.show(rows, notes);
          if (options.count > 0 && round >= options.count) break;
          co_await pause_until(round_start + interval, stopping);
        }
        co_return 0;
      });
}

}  // namespace

Subcommand add_watch(CLI::App& app, FamilyList families, FamilyCommandsList commands) {
  auto bus = std::make_shared<BusOptions>();
  auto options = std::make_shared<WatchOptions>();
  CLI::App* watch = app.add_subcommand("watch", "poll sensors in turn and show their angles, one "
                                                "row each (the Multi-Unit Angle Display)");
  add_bus_options(*watch, *bus, families);
  watch->add_option("--count", options->count, "stop after this many rounds (plain lines)")
      ->check(CLI::Range(1, 100'000'000));
  watch->add_option("--interval", options->interval_ms, "ms from one round to the next")
      ->check(CLI::Range(10, 3'600'000))
      ->capture_default_str();
  watch->add_option("--log", options->log,
                    "append every reading to this CSV file (time, address, serial, x_deg, "
                    "y_deg, tilt_deg, status)");
  watch->footer(watch_help_footer(commands));
  return {watch, [bus, options, families] { return watch_command(*bus, *options, families); },
          true};
}

}  // namespace tiltgate
