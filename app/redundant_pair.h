// The gateway as one of a redundant pair ([redundancy], docs/operations.md "Warm standby"):
// its lines kept by a RedundancyController (redundancy/redundancy_controller.h), which opens
// each only while this gateway is the active one and otherwise listens to it, and the peer it
// asks. Made by ServedGateway when the configuration has the section.
#pragma once

#include <boost/asio/any_io_executor.hpp>
#include <memory>

#include "config/config.h"
#include "driver/family.h"
#include "gateway/gateway.h"
#include "redundancy/redundancy_controller.h"

namespace tiltgate {

// The controller for `config`'s pair, given the gateway's lines (Gateway::keep_lines_with).
std::unique_ptr<RedundancyController> make_redundant_pair(boost::asio::any_io_executor executor,
                                                          const Config& config,
                                                          FamilyList families, Gateway& gateway);

}  // namespace tiltgate
