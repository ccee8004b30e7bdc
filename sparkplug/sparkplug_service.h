// The Sparkplug B edge node ([sparkplug], sparkplug/edge_node.h) as a service attached to the
// gateway (gateway/gateway_service.h): made when the table is there, restarted (NDEATH, then a
// new connection with the next bdSeq) when a reload changes the table or the sensors' names.
#pragma once

#include <boost/asio/any_io_executor.hpp>
#include <memory>
#include <optional>
#include <string>
#include <vector>

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
  SparkplugService(boost::asio::any_io_executor executor, const Gateway& gateway,
                   FamilyList families, const SparkplugConfig& config);
  ~SparkplugService() override;

  // Nothing before the switch to [server] user: the node's state_dir is that user's.
  void start() override {}
  void start_as_user() override;
  bool reload(const Config& loaded, const ConfigDiff& diff) override;
  void stop() override;
  std::string_view name() const override { return "sparkplug"; }

  // The edge node's counters and its store's; none while [sparkplug] is off (or did not start).
  std::optional<SparkplugStats> stats() const;
  std::optional<StoreStats> store_stats() const;

 private:
  void make_node();
  // A node that could not start, made and started anew (StartRetry): true once it runs.
  bool start_again();
  void log_started();

  boost::asio::any_io_executor executor_;
  const Gateway& gateway_;
  FamilyList families_;
  SparkplugConfig config_;
  std::vector<std::string> devices_;  // the sensors' names the node was made for
  std::unique_ptr<sparkplug::EdgeNode> node_;  // none without [sparkplug]
  bool started_ = false;
  // Nodes a reload replaced, freed (their client's socket with them) once stopped and their
  // last DCMD write is answered.
  Retired<sparkplug::EdgeNode> retired_;
  StartRetry retry_;  // while the node could not start
};

}  // namespace tiltgate
