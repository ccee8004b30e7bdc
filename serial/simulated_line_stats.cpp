#include "serial/simulated_line_stats.h"

#include <fcntl.h>

#include <boost/asio/steady_timer.hpp>
#include <chrono>
#include <cstdio>
#include <span>

#include <nlohmann/json.hpp>
#include <spdlog/spdlog.h>

#include "store/file_io.h"

namespace tiltgate {
namespace {

// Often enough for a test polling it, seldom enough to cost the simulator nothing.
constexpr std::chrono::milliseconds kRewriteEvery{100};

// FILE.tmp renamed over FILE: a reader sees the old object or the new one, whole.
Expected<Done, std::string> replace_stats_file(const std::string& path, const std::string& text) {
  const std::string temporary = path + ".tmp";
  {
    auto fd = store::open_file(temporary, O_WRONLY | O_CREAT | O_TRUNC);
    if (!fd) return Unexpected(fd.error());
    const std::span<const std::uint8_t> bytes(reinterpret_cast<const std::uint8_t*>(text.data()),
                                              text.size());
    if (auto written = store::write_all(fd->get(), bytes, temporary); !written) return written;
  }
  if (std::rename(temporary.c_str(), path.c_str()) != 0) {
    return Unexpected(store::errno_text("cannot rename to", path));
  }
  return Done{};
}

}  // namespace

std::string simulated_line_stats_json(const SimulatedLineStats& stats) {
  nlohmann::ordered_json masters = nlohmann::ordered_json::array();
  for (const SimulatedMasterStats& master : stats.masters) {
    masters.push_back({{"link", master.link},
                       {"bytes_sent", master.bytes_sent},
                       {"bytes_received", master.bytes_received}});
  }
  const nlohmann::ordered_json object = {{"masters", std::move(masters)},
                                         {"collisions", stats.collisions},
                                         {"master_collisions", stats.master_collisions},
                                         {"device_replies", stats.device_replies}};
  // A path that is not UTF-8 gets U+FFFD for its bad bytes instead of an exception.
  return object.dump(-1, ' ', false, nlohmann::ordered_json::error_handler_t::replace) + "\n";
}

struct SimulatedLineStatsFile::Rewrites {
  Rewrites(boost::asio::io_context& io, std::string path, Source source)
      : timer(io), path(std::move(path)), source(std::move(source)) {}

  Expected<Done, std::string> write() const {
    return replace_stats_file(path, simulated_line_stats_json(source()));
  }

  // A failure is said once, not ten times a second; a success after it is said too.
  void write_and_say() {
    const auto written = write();
    if (!written && !failing) spdlog::warn("sim: --stats: {}", written.error());
    if (written && failing) spdlog::info("sim: --stats: {} written again", path);
    failing = !written;
  }

  // The next rewrite; the handler holds `self`, so it outlives the file's owner.
  static void later(const std::shared_ptr<Rewrites>& self) {
    self->timer.expires_after(kRewriteEvery);
    self->timer.async_wait([self](const boost::system::error_code& ec) {
      if (ec || !self->running) return;
      self->write_and_say();
      later(self);
    });
  }

  boost::asio::steady_timer timer;
  std::string path;
  Source source;
  bool running = false;
  bool failing = false;
};

SimulatedLineStatsFile::SimulatedLineStatsFile(boost::asio::io_context& io, std::string path,
                                               Source source)
    : rewrites_(std::make_shared<Rewrites>(io, std::move(path), std::move(source))) {}

SimulatedLineStatsFile::~SimulatedLineStatsFile() {
  rewrites_->running = false;
  rewrites_->timer.cancel();
}

Expected<Done, std::string> SimulatedLineStatsFile::start() {
  if (auto written = rewrites_->write(); !written) return written;
  if (!rewrites_->running) {
    rewrites_->running = true;
    Rewrites::later(rewrites_);
  }
  return Done{};
}

void SimulatedLineStatsFile::stop() {
  if (!rewrites_->running) return;
  rewrites_->running = false;
  rewrites_->timer.cancel();
  rewrites_->write_and_say();
}

}  // namespace tiltgate
