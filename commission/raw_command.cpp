// `tiltgate raw`: the vendor User App's command section. One request built by the bus's family
// from a function number and data (RawDescriptor, driver/family_commands.h), sent once; the exact bytes
// each way in hex, the checksum's verdict from the family's framer, and the reply decoded.
#include <fmt/format.h>
#include <iostream>

#include "driver/hex.h"
#include "commission/commands.h"
#include "commission/commission_run.h"

namespace tiltgate {

namespace {

namespace asio = boost::asio;

struct RawOptions {
  std::int64_t function = 0;
  std::string data;  // hex bytes; empty: none
};

std::string sent_text(const LineRequest& request) {
  std::string text = "sent:     " + hex_bytes(request.bytes);
  if (request.address_bytes > 0)
    text += fmt::format("  (the first {} with the 9th bit set)",
                        request.address_bytes == 1 ? std::string("byte")
                                                   : fmt::format("{} bytes", request.address_bytes));
  return text;
}

asio::awaitable<int> raw_work(CommissionBus& bus, const bool& stopping, const RawOptions& raw,
                              FamilyCommandsList commands) {
  if (bus.sensors().size() != 1) {
    std::cerr << "tiltgate raw: give one sensor (--address A, or --config FILE --sensor NAME)\n";
    co_return 2;
  }
  const CommissionedSensor& sensor = bus.sensors().front();
  const ProtocolEntry protocol = find_protocol(bus.families(), bus.config().protocol);
  const FamilyCommands* family = find_commands(commands, protocol.family);
  if (!family || !family->raw.make) {
    std::cerr << fmt::format("tiltgate raw: no raw requests on a {} bus\n", bus.config().protocol);
    co_return 2;
  }
  const std::optional<std::vector<std::uint8_t>> data = parse_hex_bytes(raw.data);
  if (!data) {
    std::cerr << fmt::format("tiltgate raw: --data: \"{}\" is not hex bytes (e.g. \"01 0A\")\n", raw.data);
    co_return 2;
  }
  const RawSetup setup{bus.config().protocol, sensor.config.address, bus.config().master_address,
                       raw.function, *data};
  auto exchange = family->raw.make(setup);
  if (!exchange) {
    std::cerr << "tiltgate raw: " << exchange.error() << "\n";
    co_return 2;
  }
  LineRequest request = (*exchange)->request();
  // Sent once: a raw request may change the sensor, and a repeat could land twice.
  request.retries = 0;
  std::cout << sent_text(request) << "\n" << std::flush;
  const ReplyFramer& framer = *request.framer;
  const auto result = co_await bus.line().transact(std::move(request));
  if (stopping) co_return 0;
  const FramerReport report = framer.report();
  if (!result) {
    std::cout << "received: nothing"
              << (report.rejected_verdict.empty() ? "" : " valid (" + report.rejected_verdict + ")")
              << "\n";
    std::cerr << "tiltgate raw: " << bus.no_reply_message(sensor) << "\n";
    co_return 1;
  }
  std::cout << fmt::format("received: {}  ({})\n", hex_bytes(report.reply), report.reply_verdict);
  const RawReply reply = (*exchange)->decode();
  std::cout << reply.text << "\n" << std::flush;
  co_return reply.refused ? 1 : 0;
}

int raw_command(const BusOptions& options, const RawOptions& raw, FamilyList families,
                FamilyCommandsList commands) {
  return run_commissioning("raw", options, families,
                           [&](CommissionBus& bus, const bool& stopping) -> asio::awaitable<int> {
                             co_return co_await raw_work(bus, stopping, raw, commands);
                           });
}

}  // namespace

Subcommand add_raw(CLI::App& app, FamilyList families, FamilyCommandsList commands) {
  auto bus = std::make_shared<BusOptions>();
  auto options = std::make_shared<RawOptions>();
  CLI::App* raw = app.add_subcommand("raw", "send one request by function number and show the "
                                            "bytes each way and the reply (the User App's "
                                            "command section)");
  add_bus_options(*raw, *bus, families);
  bus->driver_optional = true;  // the request is built here: no device profile needed
  raw->get_option("--address")->allow_extra_args(false);
  raw->add_option("--function", options->function, "the function / command number (see below)")
      ->required();
  raw->add_option("--data", options->data, "the request's data bytes in hex, e.g. \"00 10\"");
  raw->footer(raw_help_footer(commands));
  return {raw,
          [bus, options, families, commands] {
            return raw_command(*bus, *options, families, commands);
          },
          true};
}

}  // namespace tiltgate
