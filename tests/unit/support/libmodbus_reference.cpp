#include "unit/support/libmodbus_reference.h"

#include <errno.h>
#include <modbus.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cstring>
#include <fmt/format.h>
#include <variant>

#include "modbus_tcp/device_identification.h"
#include "modbus_tcp/modbus_request.h"

namespace tiltgate::test {

namespace {

std::string system_error(const char* what) {
  return fmt::format("{}: {}", what, std::strerror(errno));
}

// The request in `adu`, if the parser accepts it and it is the one the caller describes.
bool is_checked(const ModbusRequest& request) {
  ParsedAdu parsed = parse_adu(request.adu);
  const auto* checked = std::get_if<ModbusRequest>(&parsed);
  return checked != nullptr && checked->function == request.function &&
         checked->address == request.address && checked->count == request.count &&
         checked->read_device_id_code == request.read_device_id_code &&
         checked->object_id == request.object_id;
}

// 43 / 14, without libmodbus: the request's MBAP header (transaction, protocol 0, a length
// that counts the unit id and the PDU, unit id) around the identification PDU, or the
// exception the handler or the objects call for.
std::vector<std::uint8_t> device_identification_reply(const ModbusRequest& request,
                                                      const ModbusResponse& response) {
  if (response.exception) return exception_reply(request.adu, *response.exception);
  auto pdu = encode_device_identification(response.device_objects, request.read_device_id_code,
                                          request.object_id);
  if (!pdu) return exception_reply(request.adu, pdu.error());
  const std::size_t length = 1 + pdu->size();
  std::vector<std::uint8_t> reply = {request.adu[0], request.adu[1], 0x00, 0x00,
                                     std::uint8_t(length >> 8), std::uint8_t(length & 0xFF),
                                     request.adu[6]};
  reply.insert(reply.end(), pdu->begin(), pdu->end());
  return reply;
}

// How many values a read's response carries in the request's table.
std::size_t values_for(const ModbusRequest& request, const ModbusResponse& response) {
  const bool bit_table =
      request.table == ModbusTable::coil || request.table == ModbusTable::discrete;
  return bit_table ? response.bits.size() : response.registers.size();
}

bool response_fits(const ModbusRequest& request, const ModbusResponse& response) {
  // A write's success carries no values.
  return request.is_write || values_for(request, response) == request.count;
}

struct MappingDeleter {
  void operator()(modbus_mapping_t* mapping) const { modbus_mapping_free(mapping); }
};
using Mapping = std::unique_ptr<modbus_mapping_t, MappingDeleter>;

// A mapping covering exactly the request's range in its table, holding the handler's values
// for a read (a write's values land in it and are thrown away: the handler did the write).
Mapping mapping_for(const ModbusRequest& request, const ModbusResponse& response) {
  const unsigned start = request.address;
  const unsigned count = request.count;
  auto in = [&](ModbusTable table) { return request.table == table ? count : 0u; };
  Mapping mapping(modbus_mapping_new_start_address(
      start, in(ModbusTable::coil), start, in(ModbusTable::discrete), start,
      in(ModbusTable::holding), start, in(ModbusTable::input)));
  if (!mapping || request.is_write) return mapping;
  for (unsigned i = 0; i < count; ++i) {
    switch (request.table) {
      case ModbusTable::coil: mapping->tab_bits[i] = response.bits[i] ? 1 : 0; break;
      case ModbusTable::discrete: mapping->tab_input_bits[i] = response.bits[i] ? 1 : 0; break;
      case ModbusTable::holding: mapping->tab_registers[i] = response.registers[i]; break;
      case ModbusTable::input: mapping->tab_input_registers[i] = response.registers[i]; break;
    }
  }
  return mapping;
}

}  // namespace

Expected<std::unique_ptr<LibmodbusReference>, std::string> LibmodbusReference::create() {
  int ends[2];
  // Non-blocking both ways: a reply (<= 260 bytes) always fits the socket buffer, and if it
  // ever did not, libmodbus must fail rather than block the event loop.
  if (socketpair(AF_UNIX, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0, ends) != 0) {
    return Unexpected(system_error("socketpair"));
  }
  // Never connected: the address only satisfies the constructor.
  modbus_t* context = modbus_new_tcp("127.0.0.1", 0);
  if (context == nullptr) {
    ::close(ends[0]);
    ::close(ends[1]);
    return Unexpected(system_error("modbus_new_tcp"));
  }
  // No reconnecting or sleeping inside libmodbus if a send fails.
  modbus_set_error_recovery(context, MODBUS_ERROR_RECOVERY_NONE);
  modbus_set_socket(context, ends[0]);
  return std::unique_ptr<LibmodbusReference>(new LibmodbusReference(context, ends[0], ends[1]));
}

LibmodbusReference::LibmodbusReference(_modbus* context, int libmodbus_end, int reply_end)
    : context_(context), libmodbus_end_(libmodbus_end), reply_end_(reply_end) {}

LibmodbusReference::~LibmodbusReference() {
  modbus_set_socket(context_, -1);
  modbus_free(context_);
  ::close(libmodbus_end_);
  ::close(reply_end_);
}

Expected<std::vector<std::uint8_t>, std::string> LibmodbusReference::encode(
    const ModbusRequest& request, const ModbusResponse& response) {
  if (!is_checked(request)) {
    return Unexpected(std::string("refusing to encode an unchecked request"));
  }
  if (request.function == modbus_function::encapsulated_interface) {
    return device_identification_reply(request, response);
  }
  discard_stale_bytes();
  const std::uint8_t* adu = request.adu.data();
  int sent = 0;
  ++libmodbus_calls_;
  if (response.exception) {
    sent = modbus_reply_exception(context_, adu, unsigned(*response.exception));
  } else if (!response_fits(request, response)) {
    sent = modbus_reply_exception(context_, adu, unsigned(ModbusException::device_failure));
  } else {
    Mapping mapping = mapping_for(request, response);
    if (!mapping) return Unexpected(system_error("modbus_mapping_new_start_address"));
    sent = modbus_reply(context_, adu, int(request.adu.size()), mapping.get());
  }
  if (sent < 0) return Unexpected(fmt::format("libmodbus reply: {}", modbus_strerror(errno)));
  return read_reply(sent);
}

Expected<std::vector<std::uint8_t>, std::string> LibmodbusReference::read_reply(int sent) {
  // libmodbus's send() on a stream socketpair has queued the whole reply before returning.
  std::vector<std::uint8_t> reply(static_cast<std::size_t>(sent));
  std::size_t got = 0;
  while (got < reply.size()) {
    const ssize_t n =
        ::recv(reply_end_, reply.data() + got, reply.size() - got, MSG_DONTWAIT);
    if (n > 0) {
      got += std::size_t(n);
    } else if (n < 0 && errno == EINTR) {
      continue;
    } else {
      return Unexpected(n == 0 ? std::string("reply socketpair closed")
                               : system_error("reading the reply from the socketpair"));
    }
  }
  return reply;
}

void LibmodbusReference::discard_stale_bytes() {
  // Only left over if an earlier read_reply failed half-way; keeps replies from mixing.
  std::uint8_t scratch[max_adu_size];
  while (::recv(reply_end_, scratch, sizeof scratch, MSG_DONTWAIT) > 0) {
  }
}

}  // namespace tiltgate::test
