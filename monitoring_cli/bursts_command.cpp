#include "monitoring_cli/bursts_command.h"

#include <fmt/format.h>

#include <fstream>
#include <iostream>
#include <memory>

#include "monitoring/burst_files.h"
#include "monitoring/utc_time.h"
#include "monitoring_cli/configured_sensor.h"
#include "monitoring_cli/csv_output.h"
#include "store/file_io.h"

namespace tiltgate {

namespace {

struct BurstsOptions {
  std::string config;
  std::string sensor;
  std::string id;  // empty: list them
  std::string output = "-";
};

// The list: one line a burst, newest first, as the console shows them.
int list(const std::vector<monitoring::BurstFile>& bursts, const std::string& sensor) {
  if (bursts.empty()) {
    std::cout << fmt::format("no bursts recorded for {}\n", sensor);
    return 0;
  }
  std::cout << "id                        trigger (UTC)             bytes\n";
  for (const monitoring::BurstFile& burst : bursts)
    std::cout << fmt::format("{:<25} {:<25} {}\n", burst.id,
                             monitoring::utc_timestamp(burst.unix_ms), burst.bytes);
  return 0;
}

int write_one(const std::filesystem::path& dir, const std::string& id,
              const std::vector<monitoring::BurstFile>& bursts, const std::string& output) {
  const std::string wanted = id == "last" ? (bursts.empty() ? "" : bursts.front().id) : id;
  if (wanted.empty()) {
    std::cerr << "tiltgate bursts: no bursts recorded\n";
    return 1;
  }
  const auto path = monitoring::burst_path(dir, wanted);
  if (!path) {
    std::cerr << fmt::format("tiltgate bursts: \"{}\" is no burst id (the list gives them: "
                             "2026-12-07T10-15-02.250Z), nor last\n", id);
    return 2;
  }
  auto bytes = store::read_whole(*path);
  if (!bytes) {
    std::cerr << fmt::format("tiltgate bursts: no burst {}: {}\n", wanted, bytes.error());
    return 1;
  }
  std::ofstream file;
  std::ostream* out = open_csv_output(output, file, "bursts");
  if (out == nullptr) return 1;
  out->write(reinterpret_cast<const char*>(bytes->data()), std::streamsize(bytes->size()));
  out->flush();
  return out->good() ? 0 : 1;
}

int run_bursts(const BurstsOptions& o, FamilyList families) {
  const auto configured = load_configured_sensor("bursts", o.config, o.sensor, families);
  if (!configured) return 1;
  const std::string& state_dir = configured->config.server.state_dir;
  if (state_dir.empty()) {
    std::cerr << "tiltgate bursts: the configuration keeps no state directory\n";
    return 1;
  }
  const std::filesystem::path dir = monitoring::burst_directory(state_dir, o.sensor);
  const std::vector<monitoring::BurstFile> bursts = monitoring::list_bursts(dir);
  if (o.id.empty()) return list(bursts, o.sensor);
  return write_one(dir, o.id, bursts, o.output);
}

}  // namespace

Subcommand add_bursts(CLI::App& app, FamilyList families) {
  auto options = std::make_shared<BurstsOptions>();
  CLI::App* command = app.add_subcommand(
      "bursts", "a sensor's burst records, from the configuration's state directory: the list, "
                "or one as CSV");
  command->add_option("-c,--config", options->config, "the gateway's configuration")
      ->required();
  command->add_option("--sensor", options->sensor, "the sensor's name")->required();
  command->add_option("--id", options->id,
                      "the burst to write as CSV: its id from the list, or last (default: list "
                      "them)");
  command->add_option("-o,--output", options->output,
                      "with --id: the CSV file, or - for stdout (default)");
  return {command, [options, families]() -> int { return run_bursts(*options, families); }};
}

}  // namespace tiltgate
