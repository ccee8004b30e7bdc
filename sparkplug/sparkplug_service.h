// The Sparkplug B edge node ([sparkplug], sparkplug/edge_node.h) as a service attached to the
// gateway (gateway/gateway_service.h): made when the table is there, restarted (NDEATH, then a
// new connection with the next bdSeq) when a reload changes the table or the sensors' names,
// and paused while the gateway is the standby of a redundant pair.
#pragma once

#include <boost/asio/any_io_executor.hpp>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "clock/clock_state.h"
#include "config/config.h"
#include "gateway/gateway.h"
#include "gateway/gateway_service.h"
#include "gateway/gateway_status.h"
#include "gateway/retired.h"
#include "gateway/start_retry.h"
#include "sparkplug/edge_node.h"

namespace tiltgate {

class SparkplugService final : public GatewayService {
 public:
  // `clock`: the system clock's state, reported as the node's Clock/ metrics.
  // `bursts`: the monitoring's (sparkplug/edge_node.h).
  SparkplugService(boost::asio::any_io_executor executor, const Gateway& gateway,
                   FamilyList families, const SparkplugConfig& config, ClockReader clock,
                   monitoring::BurstSource bursts = {});
  ~SparkplugService() override;

  // Nothing before the switch to [server] user: the node's state_dir is that user's.
  void start() override {}
  void start_as_user() override;
  bool reload(const Config& loaded, const ConfigDiff& diff) override;
  void stop() override;
  std::string_view name() const override { return "sparkplug"; }

  // On a redundant pair only the active gateway is the edge node (app/served_gateway.cpp): a
  // host must never see two of the same id connected. pause() stops it (NDEATH, then a clean
  // DISCONNECT) and keeps it from starting, at start-up and at a reload alike, which then only
  // take the new table; resume() starts a new edge node, as a reload does (a stopped one does
  // not start again), whose CONNECT has the next bdSeq. Not before start_as_user(): the
  // state_dir's files are the serving user's.
  void pause();
  void resume();

  // The edge node's counters and its store's; none while [sparkplug] is off, the node paused
  // (or it did not start).
  std::optional<SparkplugStats> stats() const;
  std::optional<StoreStats> store_stats() const;

 private:
  void make_node();
  // Stops the node (if it runs) and hands it to retired_, keeping its last bdSeq for the next.
  void retire_node();
  // A node that could not start, made and started anew (StartRetry): true once it runs.
  bool start_again();
  void log_started();

  boost::asio::any_io_executor executor_;
  const Gateway& gateway_;
  FamilyList families_;
  SparkplugConfig config_;
  ClockReader clock_;
  monitoring::BurstSource bursts_;
  std::vector<std::string> devices_;  // the sensors' names the node was made for
  std::unique_ptr<sparkplug::EdgeNode> node_;  // none without [sparkplug], and while paused
  bool started_ = false;
  bool paused_ = false;
  // The last will's bdSeq of the nodes before (EdgeNode::last_bd_seq()): the next goes on from
  // it, whether or not the disk took it.
  std::optional<std::uint8_t> last_bd_seq_;
  // Nodes a reload replaced, freed (their client's socket with them) once stopped and their
  // last DCMD write is answered.
  Retired<sparkplug::EdgeNode> retired_;
  StartRetry retry_;  // while the node could not start
};

}  // namespace tiltgate
