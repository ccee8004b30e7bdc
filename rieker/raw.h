// `tiltgate raw` on a Rieker bus: --function is the command code (FUNCT, e.g. 37 Get Serial),
// --data the DATA bytes; the reply decoded by the codec (rieker/codec.h).
#pragma once

#include <memory>
#include <string>

#include "driver/family_commands.h"

namespace tiltgate::rieker {

inline constexpr std::string_view kRawFunctionHelp =
    "rieker: the command code (FUNCT 0..65535, e.g. 37 Get Serial, 5 Get Angle with data 04), "
    "--data its DATA bytes; DEST, SRC, DL and the CRC are added";

Expected<std::unique_ptr<RawExchange>, std::string> make_raw_exchange(const RawSetup& setup);

}  // namespace tiltgate::rieker
