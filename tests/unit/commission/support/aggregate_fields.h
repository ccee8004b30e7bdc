// How many fields an aggregate struct has, counted by the compiler: the most values T{...}
// takes from a stand-in that converts to any field's type. For tests that check a message
// carries every field of its struct, so a field added to an event or an option later without
// its JSON fails a test instead of silently staying behind.
#pragma once

#include <cstddef>

namespace tiltgate::test {

// Converts to a reference of any type: only ever used in unevaluated braces.
struct AnyFieldValue {
  template <class T>
  operator T&() const&&;
};

template <class T, class... Values>
constexpr std::size_t aggregate_field_count() {
  if constexpr (requires { T{Values{}..., AnyFieldValue{}}; })
    return aggregate_field_count<T, Values..., AnyFieldValue>();
  else
    return sizeof...(Values);
}

}  // namespace tiltgate::test
