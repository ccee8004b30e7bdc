// Runs one coroutine on an io_context to completion (or a generous deadline) from a test.
#pragma once

#include <boost/asio/awaitable.hpp>
#include <boost/asio/co_spawn.hpp>
#include <boost/asio/io_context.hpp>
#include <chrono>
#include <exception>
#include <optional>
#include <stdexcept>

namespace tiltgate::test {

template <class T>
T run_coroutine(boost::asio::io_context& io, boost::asio::awaitable<T> coroutine,
                std::chrono::seconds limit = std::chrono::seconds(20)) {
  std::optional<T> result;
  std::exception_ptr failure;
  // co_spawn needs a default-constructible result type; Expected is not, so wrap it.
  auto wrapped = [](boost::asio::awaitable<T> inner) -> boost::asio::awaitable<std::optional<T>> {
    co_return co_await std::move(inner);
  };
  boost::asio::co_spawn(io, wrapped(std::move(coroutine)),
                        [&](std::exception_ptr e, std::optional<T> value) {
                          failure = e;
                          if (!e) result = std::move(value);
                        });
  const auto deadline = std::chrono::steady_clock::now() + limit;
  while (!result && !failure && std::chrono::steady_clock::now() < deadline) {
    io.restart();
    io.run_one_for(std::chrono::milliseconds(50));
  }
  if (failure) std::rethrow_exception(failure);
  if (!result) throw std::runtime_error("coroutine did not finish in time");
  return std::move(*result);
}

inline void run_coroutine(boost::asio::io_context& io, boost::asio::awaitable<void> coroutine,
                          std::chrono::seconds limit = std::chrono::seconds(20)) {
  auto wrapped = [](boost::asio::awaitable<void> inner) -> boost::asio::awaitable<bool> {
    co_await std::move(inner);
    co_return true;
  };
  run_coroutine(io, wrapped(std::move(coroutine)), limit);
}

// Lets the io_context run handlers for a while (reopen timers, simulator replies).
inline void run_for(boost::asio::io_context& io, std::chrono::milliseconds duration) {
  io.restart();
  io.run_for(duration);
}

}  // namespace tiltgate::test
