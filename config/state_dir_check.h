// Whether the gateway's user could keep files in a state directory (docs/operations.md, "The
// state directory"), checked without creating anything, so `tiltgate check` leaves the disk as
// it was: the directory itself when it exists, else the nearest folder above it that does,
// which must let this user create it.
#pragma once

#include <filesystem>
#include <optional>
#include <string>

namespace tiltgate::config {

// None when this user may create and write `dir`; else why not ("/var/lib is not writable by
// uid 1000: Permission denied").
std::optional<std::string> state_dir_problem(const std::filesystem::path& dir);

}  // namespace tiltgate::config
