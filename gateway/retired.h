// What a reload replaced (a service's server, feed or edge node; a bus), kept only until
// nothing refers to it any more, then freed with its descriptors: stopped, its last work (a
// write waiting for a bus, a connection being answered) may still be under way. Each object
// says when it is done (T::finished()); they are looked at when one is added and then every
// second while any is left. On the event loop's thread only.
#pragma once

#include <boost/asio/any_io_executor.hpp>
#include <boost/asio/steady_timer.hpp>
#include <chrono>
#include <memory>
#include <vector>

namespace tiltgate {

template <class T>
class Retired {
 public:
  explicit Retired(boost::asio::any_io_executor executor) : timer_(std::move(executor)) {}
  Retired(const Retired&) = delete;
  Retired& operator=(const Retired&) = delete;

  // `object` has been stopped.
  void add(std::unique_ptr<T> object) {
    if (object) objects_.push_back(std::move(object));
    free_finished();
  }
  // The objects not freed yet: still in use.
  std::size_t size() const { return objects_.size(); }

 private:
  void free_finished() {
    std::erase_if(objects_, [](const std::unique_ptr<T>& object) { return object->finished(); });
    if (objects_.empty() || waiting_) return;
    waiting_ = true;
    timer_.expires_after(std::chrono::seconds(1));
    timer_.async_wait([this](const boost::system::error_code& ec) {
      if (ec) return;  // destroyed with the service: nothing of this is touched
      waiting_ = false;
      free_finished();
    });
  }

  boost::asio::steady_timer timer_;
  std::vector<std::unique_ptr<T>> objects_;
  bool waiting_ = false;
};

}  // namespace tiltgate
