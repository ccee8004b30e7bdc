#include "commission/raw_engine.h"

#include <fmt/format.h>

#include "driver/hex.h"

namespace tiltgate {

boost::asio::awaitable<int> raw_exchange(CommissionBus& bus, const RawOptions& raw,
                                         FamilyCommandsList commands, const EventSink& report,
                                         const bool& stopping) {
  if (bus.sensors().size() != 1) {
    report(FailedEvent{2, "give one sensor (--address A, or --config FILE --sensor NAME)"});
    co_return 2;
  }
  const CommissionedSensor& sensor = bus.sensors().front();
  const ProtocolEntry protocol = find_protocol(bus.families(), bus.config().protocol);
  const FamilyCommands* family = find_commands(commands, protocol.family);
  if (!family || !family->raw.make) {
    report(FailedEvent{2, fmt::format("no raw requests on a {} bus", bus.config().protocol)});
    co_return 2;
  }
  const std::optional<std::vector<std::uint8_t>> data = parse_hex_bytes(raw.data);
  if (!data) {
    report(FailedEvent{2, fmt::format("--data: \"{}\" is not hex bytes (e.g. \"01 0A\")", raw.data)});
    co_return 2;
  }
  const RawSetup setup{bus.config().protocol, sensor.config.address, bus.config().master_address,
                       raw.function, *data};
  auto exchange = family->raw.make(setup);
  if (!exchange) {
    report(FailedEvent{2, exchange.error()});
    co_return 2;
  }
  LineRequest request = (*exchange)->request();
  // Sent once: a raw request may change the sensor, and a repeat could land twice.
  request.retries = 0;
  ExchangeEvent event;
  event.sent = request.bytes;
  event.address_bytes = request.address_bytes;
  const ReplyFramer& framer = *request.framer;
  const auto result = co_await bus.line().transact(std::move(request));
  if (stopping) co_return 0;
  const FramerReport framed = framer.report();
  if (!result) {
    event.rejected_verdict = framed.rejected_verdict;
    report(event);
    report(FailedEvent{1, bus.no_reply_message(sensor)});
    co_return 1;
  }
  const RawReply reply = (*exchange)->decode();
  event.answered = true;
  event.received = framed.reply;
  event.verdict = framed.reply_verdict;
  event.decoded = reply.text;
  event.refused = reply.refused;
  report(event);
  co_return reply.refused ? 1 : 0;
}

}  // namespace tiltgate
