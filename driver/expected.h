// A value or an error: the error channel for everything that runs inside the event loop
// (std::expected is C++23; Debian 12's g++ 12 does not have it).
#pragma once

#include <utility>
#include <variant>

namespace tiltgate {

// The constructor makes Unexpected(x) valid for every compiler: without one it is a
// parenthesised aggregate initialisation, which clang 14 does not implement.
template <class E>
struct Unexpected {
  explicit Unexpected(E e) : error(std::move(e)) {}
  E error;
};
template <class E>
Unexpected(E) -> Unexpected<E>;

template <class T, class E>
class Expected {
 public:
  Expected(T value) : v_(std::in_place_index<0>, std::move(value)) {}
  template <class G>
  Expected(Unexpected<G> e) : v_(std::in_place_index<1>, E(std::move(e.error))) {}

  bool has_value() const { return v_.index() == 0; }
  explicit operator bool() const { return has_value(); }
  T& value() { return std::get<0>(v_); }
  const T& value() const { return std::get<0>(v_); }
  T& operator*() { return value(); }
  const T& operator*() const { return value(); }
  T* operator->() { return &value(); }
  const T* operator->() const { return &value(); }
  const E& error() const { return std::get<1>(v_); }

 private:
  std::variant<T, E> v_;
};

// Success carries nothing.
struct Done {};

}  // namespace tiltgate
