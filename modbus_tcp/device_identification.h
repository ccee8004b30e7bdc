// Function 43 / MEI type 14, Read Device Identification (Modbus Application Protocol V1.1b3,
// section 6.21), answered by the gateway itself: libmodbus 3.1.6 does not serve it. Pure: a
// unit's objects in, the response PDU out, with the spec's categories, stream and individual
// access, and paging ("more follows") when the objects do not fit one 253-byte PDU.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "driver/expected.h"
#include "modbus_tcp/modbus_types.h"

namespace tiltgate {

// MEI type 14 of function 43 (43 / 13 is CANopen General Reference, not served).
inline constexpr std::uint8_t mei_read_device_identification = 0x0E;

// Read Device ID codes (section 6.21).
namespace read_device_id {
inline constexpr std::uint8_t basic_stream = 0x01;     // objects 0x00..0x02
inline constexpr std::uint8_t regular_stream = 0x02;   // ... and 0x03..0x7F
inline constexpr std::uint8_t extended_stream = 0x03;  // ... and 0x80..0xFF
inline constexpr std::uint8_t one_object = 0x04;       // individual access, any category
}  // namespace read_device_id

// Object ids. 0x00..0x06 are the spec's; 0x07..0x7F are reserved by it; 0x80..0xFF are
// "private objects ... device dependent", where the gateway puts what a commissioning engineer
// needs to tell one sensor from another.
namespace device_object {
inline constexpr std::uint8_t vendor_name = 0x00;            // basic
inline constexpr std::uint8_t product_code = 0x01;           // basic
inline constexpr std::uint8_t major_minor_revision = 0x02;   // basic
inline constexpr std::uint8_t vendor_url = 0x03;             // regular, optional
inline constexpr std::uint8_t product_name = 0x04;           // regular
inline constexpr std::uint8_t model_name = 0x05;             // regular
inline constexpr std::uint8_t user_application_name = 0x06;  // regular
inline constexpr std::uint8_t serial_number = 0x80;          // extended (tiltgate)
inline constexpr std::uint8_t sensor_name = 0x81;            // extended (tiltgate)
inline constexpr std::uint8_t bus_name = 0x82;               // extended (tiltgate)
inline constexpr std::uint8_t bus_address = 0x83;            // extended (tiltgate)
inline constexpr std::uint8_t gateway_version = 0x84;        // extended (tiltgate)
}  // namespace device_object

// The largest PDU (section 4.1), and so the longest object value that fits a response on its
// own: the PDU less the 7 header bytes and the object's id and length bytes. Longer values are
// cut to this length.
inline constexpr std::size_t max_pdu_size = 253;
inline constexpr std::size_t max_device_object_size = max_pdu_size - 7 - 2;

// 1 basic, 2 regular, 3 extended: the stream code that first includes `id`.
std::uint8_t device_object_category(std::uint8_t id);

// The conformity level byte: 0x80 (individual access is supported) plus the highest category
// among `objects` (0x81, 0x82 or 0x83).
std::uint8_t conformity_level(std::span<const DeviceObject> objects);

// The response PDU, function code first, to a request with `read_code` and `object_id`, from
// all of a unit's `objects` (any order, each id once):
//   - stream access (codes 1..3) answers every object of that category and the ones below it,
//     in id order, from `object_id` on; an `object_id` that is not such an object restarts at
//     the first one (the spec: "as if object 0 were pointed out"). Objects that do not fit are
//     left for the next request: more follows = 0xFF and next object id = the first one left;
//   - individual access (code 4) answers the one object, of any category, or exception 02;
//   - any other code is exception 03.
Expected<std::vector<std::uint8_t>, ModbusException> encode_device_identification(
    std::span<const DeviceObject> objects, std::uint8_t read_code, std::uint8_t object_id);

}  // namespace tiltgate
