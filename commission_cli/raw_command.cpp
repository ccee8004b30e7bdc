// `tiltgate raw` on the command line: the engine's request (commission/raw_engine.h) shown as
// text, the exact bytes each way in hex, the checksum's verdict and the reply decoded.
#include <fmt/format.h>
#include <iostream>

#include "commission_cli/commands.h"
#include "commission_cli/commission_run.h"
#include "commission/event_text.h"
#include "commission/raw_engine.h"

namespace tiltgate {

namespace {

namespace asio = boost::asio;

// The request's events as the command line shows them: the bytes each way and the reply
// decoded on stdout, a failure as "tiltgate raw: ..." on stderr.
void show(const CommissionEvent& event) {
  if (const auto* exchange = std::get_if<ExchangeEvent>(&event)) {
    std::cout << exchange_text(*exchange) << std::flush;
  } else if (const auto* failed = std::get_if<FailedEvent>(&event)) {
    std::cerr << "tiltgate raw: " << failed->message << "\n";
  } else if (const auto* note = std::get_if<NoteEvent>(&event)) {
    std::cerr << "tiltgate raw: " << (note->warning ? "warning: " : "") << note->text << "\n";
  }
}

int raw_command(const BusOptions& options, const RawOptions& raw, FamilyList families,
                FamilyCommandsList commands) {
  const EventSink report = show;
  return run_commissioning("raw", options, families,
                           [&](CommissionBus& bus, const bool& stopping) -> asio::awaitable<int> {
                             co_return co_await raw_exchange(bus, raw, commands, report,
                                                             stopping);
                           },
                           GatewayRequest{CommandRequest{"raw", options, {}, raw, {}, {}},
                                          report, nullptr});
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
