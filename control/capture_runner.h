// `tiltgate capture --bus NAME` through the control socket (capture_cli/capture_command.h): a
// `run` whose request is a capture is answered from the bus's black box (capture/black_box.h),
// not by the commissioning engine, and never touches the line.
//
//   {"command": "capture", "last": true}    the black box: every frame it holds, then exit 0
//   {"command": "capture", "seconds": 10}   the frames from now on for 10 s (0: until stopped)
//
// Events: first {"event": "capture", "bus", "protocol", "dissector", "keep_s"}, then one
// {"event": "frame", ...} per frame (capture/frame_json.h), in the order they were on the
// wire, and {"event": "missed", "frames": N} where frames went before they could be sent (a
// reader slower than the line for longer than the black box keeps). Each capture is one record
// of the audit trail (frames carry settings): door and person as the session says, the bus,
// "capture", "last 60 s" or "live 10 s".
#pragma once

#include <string>

#include "control/command_runner.h"

namespace tiltgate {

// Whether `request` (one JSON object) asks for a capture.
bool is_capture_request(const std::string& request);

// A runner that answers capture requests itself and hands every other request to
// `commissioning`.
CommandRunner with_capture(CommandRunner commissioning);

}  // namespace tiltgate
