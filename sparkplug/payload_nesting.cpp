#include "sparkplug/payload_nesting.h"

#include <optional>

namespace tiltgate::sparkplug {
namespace {

// The messages of sparkplug_b.proto that hold other messages; Leaf stands for those that hold
// none (MetaData and the extension placeholders), whose content is not looked into.
enum class Message {
  Payload,
  Metric,
  PropertySet,
  PropertyValue,
  PropertySetList,
  DataSet,
  Row,
  DataSetValue,
  Template,
  Parameter,
  Leaf,
};

// The message a length-delimited field holds, by the field numbers of sparkplug_b.proto;
// none for a string, bytes or a packed scalar.
std::optional<Message> nested_message(Message parent, std::uint64_t field) {
  switch (parent) {
    case Message::Payload:
      if (field == 2) return Message::Metric;
      break;
    case Message::Metric:
      if (field == 8 || field == 19) return Message::Leaf;  // metadata, extension_value
      if (field == 9) return Message::PropertySet;
      if (field == 17) return Message::DataSet;
      if (field == 18) return Message::Template;
      break;
    case Message::PropertySet:
      if (field == 2) return Message::PropertyValue;
      break;
    case Message::PropertyValue:
      if (field == 9) return Message::PropertySet;
      if (field == 10) return Message::PropertySetList;
      if (field == 11) return Message::Leaf;
      break;
    case Message::PropertySetList:
      if (field == 1) return Message::PropertySet;
      break;
    case Message::DataSet:
      if (field == 4) return Message::Row;
      break;
    case Message::Row:
      if (field == 1) return Message::DataSetValue;
      break;
    case Message::DataSetValue:
      if (field == 7) return Message::Leaf;
      break;
    case Message::Template:
      if (field == 2) return Message::Metric;
      if (field == 3) return Message::Parameter;
      break;
    case Message::Parameter:
      if (field == 9) return Message::Leaf;
      break;
    case Message::Leaf: break;
  }
  return std::nullopt;
}

// Reads a base-128 varint (at most 10 bytes) at `at`, moving it past the varint.
std::optional<std::uint64_t> read_varint(std::span<const std::uint8_t> bytes, std::size_t& at) {
  std::uint64_t value = 0;
  for (int shift = 0; shift < 64 && at < bytes.size(); shift += 7) {
    const std::uint8_t b = bytes[at++];
    value |= static_cast<std::uint64_t>(b & 0x7F) << shift;
    if ((b & 0x80) == 0) return value;
  }
  return std::nullopt;
}

bool well_formed(std::span<const std::uint8_t> bytes, Message message, int depth) {
  if (depth > kMaxNesting) return false;
  std::size_t at = 0;
  while (at < bytes.size()) {
    const auto tag = read_varint(bytes, at);
    if (!tag || (*tag >> 3) == 0) return false;
    const std::uint64_t field = *tag >> 3;
    std::uint64_t skip = 0;
    switch (*tag & 7) {
      case 0:  // varint
        if (!read_varint(bytes, at)) return false;
        break;
      case 1:  // fixed64
        skip = 8;
        break;
      case 5:  // fixed32
        skip = 4;
        break;
      case 2: {  // length-delimited
        const auto length = read_varint(bytes, at);
        if (!length || *length > bytes.size() - at) return false;
        const auto inner = nested_message(message, field);
        if (inner && *inner != Message::Leaf &&
            !well_formed(bytes.subspan(at, *length), *inner, depth + 1)) {
          return false;
        }
        skip = *length;
        break;
      }
      default:  // groups (3, 4) are not in the schema; 6 and 7 do not exist
        return false;
    }
    if (skip > bytes.size() - at) return false;
    at += skip;
  }
  return true;
}

}  // namespace

bool nesting_within_limit(std::span<const std::uint8_t> bytes) {
  return well_formed(bytes, Message::Payload, 1);
}

}  // namespace tiltgate::sparkplug
