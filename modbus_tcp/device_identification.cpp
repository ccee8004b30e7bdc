#include "modbus_tcp/device_identification.h"

#include <algorithm>

namespace tiltgate {

namespace {

constexpr std::uint8_t function_code = 0x2B;
constexpr std::uint8_t no_more_follows = 0x00;
constexpr std::uint8_t more_follows = 0xFF;

// Function, MEI type, Read Device ID code, conformity level, more follows, next object id,
// number of objects (section 6.21, response).
constexpr std::size_t header_size = 7;
constexpr std::size_t more_follows_at = 4;
constexpr std::size_t next_object_at = 5;
constexpr std::size_t count_at = 6;
static_assert(max_device_object_size == max_pdu_size - header_size - 2);

std::vector<const DeviceObject*> in_id_order(std::span<const DeviceObject> objects) {
  std::vector<const DeviceObject*> sorted;
  for (const DeviceObject& object : objects) sorted.push_back(&object);
  std::stable_sort(sorted.begin(), sorted.end(),
                   [](const DeviceObject* a, const DeviceObject* b) { return a->id < b->id; });
  return sorted;
}

std::size_t value_size(const DeviceObject& object) {
  return std::min(object.value.size(), max_device_object_size);
}

void append(std::vector<std::uint8_t>& pdu, const DeviceObject& object) {
  const std::size_t size = value_size(object);
  pdu.push_back(object.id);
  pdu.push_back(std::uint8_t(size));
  pdu.insert(pdu.end(), object.value.begin(), object.value.begin() + std::ptrdiff_t(size));
}

}  // namespace

std::uint8_t device_object_category(std::uint8_t id) {
  if (id <= device_object::major_minor_revision) return read_device_id::basic_stream;
  if (id < 0x80) return read_device_id::regular_stream;
  return read_device_id::extended_stream;
}

std::uint8_t conformity_level(std::span<const DeviceObject> objects) {
  std::uint8_t highest = read_device_id::basic_stream;
  for (const DeviceObject& object : objects) {
    highest = std::max(highest, device_object_category(object.id));
  }
  return std::uint8_t(0x80 | highest);
}

Expected<std::vector<std::uint8_t>, ModbusException> encode_device_identification(
    std::span<const DeviceObject> objects, std::uint8_t read_code, std::uint8_t object_id) {
  if (read_code < read_device_id::basic_stream || read_code > read_device_id::one_object) {
    return Unexpected(ModbusException::illegal_value);
  }
  std::vector<std::uint8_t> pdu = {function_code, mei_read_device_identification, read_code,
                                   conformity_level(objects), no_more_follows, 0x00, 0};
  const auto sorted = in_id_order(objects);

  if (read_code == read_device_id::one_object) {
    auto found = std::find_if(sorted.begin(), sorted.end(),
                              [&](const DeviceObject* o) { return o->id == object_id; });
    if (found == sorted.end()) return Unexpected(ModbusException::illegal_address);
    append(pdu, **found);
    pdu[count_at] = 1;
    return pdu;
  }

  std::vector<const DeviceObject*> stream;
  for (const DeviceObject* object : sorted) {
    if (device_object_category(object->id) <= read_code) stream.push_back(object);
  }
  auto start = std::find_if(stream.begin(), stream.end(),
                            [&](const DeviceObject* o) { return o->id == object_id; });
  if (start == stream.end()) start = stream.begin();
  for (auto it = start; it != stream.end(); ++it) {
    if (pdu.size() + 2 + value_size(**it) > max_pdu_size) {
      pdu[more_follows_at] = more_follows;
      pdu[next_object_at] = (*it)->id;
      break;
    }
    append(pdu, **it);
    ++pdu[count_at];
  }
  return pdu;
}

}  // namespace tiltgate
