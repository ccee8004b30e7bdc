// The Rieker Flex (H6 dual axis, H4360 single axis) RS485 protocol, as pure functions: frames,
// their encoding, and typed requests and replies for the 15 user functions. No I/O here.
// Source: the H6/H4360 manual, "Digital RS485 Communications", with the errata listed in
// docs/protocols.md, "Rieker errata" (its example CRCs were checked by computation; some are
// wrong).
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "driver/expected.h"

namespace tiltgate::rieker {

// ---- Frame layout ("Packet Format"): [DEST u16][SRC u16][FUNCT u16][DL u8][DATA][CRC u16] ----
inline constexpr std::size_t kHeaderSize = 7;
inline constexpr std::size_t kCrcSize = 2;
inline constexpr std::size_t kMaxDataSize = 255;  // DL is one byte
inline constexpr std::size_t kMinFrameSize = kHeaderSize + kCrcSize;        // 9
inline constexpr std::size_t kMaxFrameSize = kMinFrameSize + kMaxDataSize;  // 264

// ---- Addresses ("Digital RS485 Communications"; docs/protocols.md, "Rieker addresses") ----
inline constexpr std::uint16_t kBroadcastAddress = 0xFFFC;
inline constexpr std::uint16_t kFactoryAddress = 223;
inline constexpr std::uint16_t kMinSensorAddress = 1;
inline constexpr std::uint16_t kMaxSensorAddress = 65000;
inline constexpr std::uint16_t kMaxMasterAddress = 65500;

// ---- Settings ----
inline constexpr std::uint32_t kLockPassword = 12345678;  // "Change Lock", sent as u32
inline constexpr int kDefaultFilter = 4;                  // "Set Filter Response": 1..6
inline constexpr int kMinFilter = 1;
inline constexpr int kMaxFilter = 6;
// "Set Baud": the text says the default is code 3, but code 3 is 115200 in its own table and
// the sensors ship at 125000 baud (stated twice): the default is code 4.
inline constexpr int kDefaultBaudCode = 4;
inline constexpr std::size_t kFirmwareSize = 7;  // "Get Firmware Revision": 7 ASCII bytes
inline constexpr std::size_t kSerialSize = 10;   // "Get Serial #": 10 ASCII bytes, space padded

// The two sensors of the family: the H6 is dual axis (X, Y), the H4360 single axis.
enum class Model { h6, h4360 };
const char* model_name(Model model);                          // "h6", "h4360"
std::optional<Model> model_from_name(std::string_view name);  // nullopt for anything else

// Table 2, "RS485 Function List". Other IDs are reserved for the factory.
enum class Function : std::uint16_t {
  ack = 0,
  nak = 1,
  set_address = 2,
  get_address = 3,
  check_address = 4,
  get_angle = 5,
  change_lock = 10,
  restart = 16,
  set_zero_to_value = 25,
  set_zero_to_angle = 26,
  get_firmware = 28,
  get_lock_level = 30,
  get_serial = 37,
  set_baud = 38,
  set_filter = 41,
};

// "get angle", or nullptr for an ID that is not a user function.
const char* function_name(std::uint16_t function);
// Whether the function changes the sensor and so needs lock level 1. The table says lock 0 for
// Set Address and Restart while their descriptions say 1; every changing function needs 1.
bool needs_unlock(Function function);

// "NAK": the error code a sensor sends back.
enum class NakCode : std::uint8_t {
  crc_failure = 0,
  unknown_function = 1,
  not_valid_for_sensor = 2,  // function not valid for this sensor or mode of operation
  data_invalid = 3,
  wrong_lock_level = 4,
  busy = 5,  // wait and try again
};
const char* nak_name(std::uint8_t code);  // "busy", or "unknown NAK code" past 5

// "Get Angle" type codes.
enum class AngleType : std::uint8_t { single_axis = 1, x = 2, y = 3, x_and_y = 4 };
// "Set Zero To Value" axis codes.
enum class Axis : std::uint8_t { x = 1, y = 2 };  // x is also the single axis of an H4360
// "Set Zero To Current Angle" type codes.
enum class ZeroPersistence : std::uint8_t { temporary = 0, permanent = 1 };
enum class LockLevel : std::uint8_t { locked = 0, unlocked = 1 };

// "Set Baud" codes 1..8 -> 9600, 38400, 115200, 125000, 128000, 250000, 19200, 62500.
std::optional<std::uint32_t> baud_for_code(int code);
std::optional<int> code_for_baud(std::uint32_t baud);

// ---- Frames ----
struct Frame {
  std::uint16_t dest = 0;
  std::uint16_t src = 0;
  std::uint16_t function = 0;
  std::vector<std::uint8_t> data;  // at most kMaxDataSize bytes

  bool operator==(const Frame&) const = default;
};

enum class DecodeError {
  too_short,        // fewer than kMinFrameSize bytes
  length_mismatch,  // the byte count is not kMinFrameSize + DL
  bad_crc,
};
const char* to_string(DecodeError error);

// Precondition: frame.data.size() <= kMaxDataSize (the request and reply builders below
// guarantee it); longer data would not fit the one-byte DL.
std::vector<std::uint8_t> encode(const Frame& frame);
// `bytes` must be exactly one frame. DL rules: the manual's ACK examples that show an extra
// 00 data byte with DL 00 are length mismatches, not ACKs.
Expected<Frame, DecodeError> decode(std::span<const std::uint8_t> bytes);

// Whether `reply` answers `request`: addressed to the request's SRC, sent by the sensor it
// addressed (any sensor, for a broadcast), with the request's function, ACK or NAK. ACKs all
// look alike, so this cannot tell a late ACK from the answer to the next request: the Line's
// guard after a time-out does (driver/line.h).
bool is_reply_to(const Frame& reply, const Frame& request);

// ---- Typed requests (master -> sensor). Arguments are checked before anything is encoded. ----
struct Route {
  std::uint16_t sensor = kFactoryAddress;  // 1..65000, or kBroadcastAddress
  std::uint16_t master = 0;                // the gateway's own address, 0..65500
};

struct ArgumentError {
  std::string message;
};
using RequestResult = Expected<Frame, ArgumentError>;

RequestResult set_address_request(Route route, std::int64_t new_address);  // 1..65000
RequestResult get_address_request(Route route);
RequestResult check_address_request(Route route);
RequestResult get_angle_request(Route route, AngleType type);
RequestResult change_lock_request(Route route, LockLevel level,
                                  std::uint32_t password = kLockPassword);
RequestResult restart_request(Route route);
// Offset in degrees, finite and within +-360 (180 on both axes mounts a sensor upside down).
RequestResult set_zero_to_value_request(Route route, Axis axis, float offset_degrees);
RequestResult set_zero_to_angle_request(Route route, ZeroPersistence persistence);
RequestResult get_firmware_request(Route route);
RequestResult get_lock_level_request(Route route);
RequestResult get_serial_request(Route route);
RequestResult set_baud_request(Route route, int baud_code);                // 1..8
RequestResult set_filter_request(Route route, int filter_response);        // 1..6

// ---- Typed replies (sensor -> master) ----
struct ReplyError {
  enum class Kind {
    nak,                  // the sensor refused: see nak_code
    unexpected_function,  // neither the expected reply nor a NAK
    wrong_length,         // the expected function with the wrong DL
    bad_data,             // the right length, but a value the protocol does not define
  };
  Kind kind = Kind::nak;
  std::uint16_t function = 0;   // the reply's FUNCT
  std::uint8_t nak_code = 0;    // kind == nak: the code as sent (may be past 5)
  std::size_t data_length = 0;  // the reply's DL
};
std::string describe(const ReplyError& error);  // for logs: "NAK 4 (wrong lock level)"

template <class T>
using ReplyResult = Expected<T, ReplyError>;

// Angles in degrees. Type 1 (single axis) fills x, type 2 x, type 3 y, type 4 both.
struct Angles {
  std::optional<float> x;
  std::optional<float> y;
};

// The replies to Set Address, Check Address, Change Lock, Restart, Set Zero, Set Baud and Set
// Filter are all an ACK.
ReplyResult<Done> parse_ack(const Frame& reply);
ReplyResult<std::uint16_t> parse_address_reply(const Frame& reply);
ReplyResult<Angles> parse_angle_reply(const Frame& reply, AngleType requested);
ReplyResult<std::string> parse_firmware_reply(const Frame& reply);  // the 7 bytes as sent
ReplyResult<LockLevel> parse_lock_level_reply(const Frame& reply);  // 0 or 1, else bad_data
ReplyResult<std::string> parse_serial_reply(const Frame& reply);  // trailing padding trimmed

// ---- Reply builders (the sensor side, for the simulator) ----
Frame make_ack(std::uint16_t to, std::uint16_t from);
Frame make_nak(std::uint16_t to, std::uint16_t from, NakCode code);
Frame make_address_reply(std::uint16_t to, std::uint16_t from);  // DATA = from
Frame make_angle_reply(std::uint16_t to, std::uint16_t from, std::span<const float> angles);
Frame make_lock_level_reply(std::uint16_t to, std::uint16_t from, LockLevel level);
// Cut or space padded to kFirmwareSize / kSerialSize bytes.
Frame make_firmware_reply(std::uint16_t to, std::uint16_t from, std::string_view firmware);
Frame make_serial_reply(std::uint16_t to, std::uint16_t from, std::string_view serial);

}  // namespace tiltgate::rieker
