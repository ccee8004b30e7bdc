// Every field of a JSON message, for tests that check a reader refuses each one left out or of
// the wrong type (commission_wire/json_fields.h): the paths of an object's leaves, as JSON pointers
// and as the reader names them in its errors ("/found/0/baud" is "found[0].baud").
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace tiltgate::test {

struct JsonLeaf {
  nlohmann::json::json_pointer pointer;
  std::string path;           // as the reader's errors name it
  bool in_object = false;     // its parent is an object (so it can be left out)
};

inline std::vector<JsonLeaf> json_leaves(const nlohmann::json& message) {
  std::vector<JsonLeaf> leaves;
  const nlohmann::json flat = message.flatten();  // kept: items() refers into it
  for (const auto& [pointer_text, value] : flat.items()) {
    JsonLeaf leaf{nlohmann::json::json_pointer(pointer_text), "", false};
    nlohmann::json::json_pointer walked;
    for (std::size_t start = 1; start <= pointer_text.size();) {
      std::size_t end = pointer_text.find('/', start);
      if (end == std::string::npos) end = pointer_text.size();
      const std::string token = pointer_text.substr(start, end - start);
      const bool index = message[walked].is_array();
      leaf.path += index ? "[" + token + "]" : (leaf.path.empty() ? "" : ".") + token;
      leaf.in_object = !index;
      walked /= token;
      start = end + 1;
    }
    leaves.push_back(std::move(leaf));
  }
  return leaves;
}

// `message` without the leaf (which must sit in an object).
inline nlohmann::json without(const nlohmann::json& message, const JsonLeaf& leaf) {
  nlohmann::json changed = message;
  changed[leaf.pointer.parent_pointer()].erase(leaf.pointer.back());
  return changed;
}

// `message` with the leaf replaced by `value`.
inline nlohmann::json with(const nlohmann::json& message, const JsonLeaf& leaf,
                           nlohmann::json value) {
  nlohmann::json changed = message;
  changed[leaf.pointer] = std::move(value);
  return changed;
}

}  // namespace tiltgate::test
