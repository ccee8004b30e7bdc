#include "monitoring_cli/history_command.h"

#include <fmt/format.h>

#include <chrono>
#include <fstream>
#include <iostream>
#include <memory>

#include "monitoring_cli/configured_sensor.h"
#include "monitoring_cli/csv_output.h"
#include "monitoring/history_csv.h"
#include "monitoring/long_record.h"
#include "monitoring/long_record_reader.h"

namespace tiltgate {

namespace {

struct HistoryOptions {
  std::string config;
  std::string sensor;
  std::string from;
  std::string to;
  std::string output = "-";
};

int history_usage_error(const std::string& message) {
  std::cerr << "tiltgate history: " << message << "\nRun with --help for more information.\n";
  return 2;
}

int run_history(const HistoryOptions& o, FamilyList families) {
  std::int64_t from = 0;
  std::int64_t to = std::chrono::duration_cast<std::chrono::milliseconds>(
                        std::chrono::system_clock::now().time_since_epoch())
                        .count() + 1;
  for (const auto& [text, value, name] :
       {std::tuple{&o.from, &from, "--from"}, std::tuple{&o.to, &to, "--to"}}) {
    if (text->empty()) continue;
    auto parsed = monitoring::parse_time_query(*text);
    if (!parsed) return history_usage_error(std::string(name) + ": " + parsed.error());
    *value = *parsed;
  }
  if (to <= from) return history_usage_error("--to must be after --from");
  const auto configured = load_configured_sensor("history", o.config, o.sensor, families);
  if (!configured) return 1;
  const Config* loaded = &configured->config;
  if (loaded->server.state_dir.empty()) {
    std::cerr << "tiltgate history: the configuration keeps no state directory\n";
    return 1;
  }
  std::ofstream file;
  std::ostream* out = open_csv_output(o.output, file, "history");
  if (out == nullptr) return 1;
  monitoring::LongRecordReader reader(
      monitoring::record_directory(loaded->server.state_dir, o.sensor), from, to);
  *out << monitoring::history_csv_header();
  for (auto rows = reader.next(); !rows.empty(); rows = reader.next())
    *out << monitoring::history_csv_rows(rows);
  for (const std::string& problem : reader.problems())
    std::cerr << "tiltgate history: " << problem << "\n";
  out->flush();
  return out->good() ? 0 : 1;
}

}  // namespace

Subcommand add_history(CLI::App& app, FamilyList families) {
  auto options = std::make_shared<HistoryOptions>();
  CLI::App* command = app.add_subcommand(
      "history", "a sensor's long record (min, mean and max per interval) as CSV, from the "
                 "configuration's state directory");
  command->add_option("-c,--config", options->config, "the gateway's configuration")
      ->required();
  command->add_option("--sensor", options->sensor, "the sensor's name")->required();
  command->add_option("--from", options->from,
                      "the first interval's start: Unix ms or UTC ISO 8601 (default: the start)");
  command->add_option("--to", options->to, "the end, not included (default: now)");
  command->add_option("-o,--output", options->output, "the CSV file, or - for stdout (default)");
  return {command, [options, families]() -> int { return run_history(*options, families); }};
}

}  // namespace tiltgate
