// Where `tiltgate history` and `tiltgate bursts` write their CSV: standard output for "-",
// else the file `path`, made anew.
#pragma once

#include <fstream>
#include <ostream>
#include <string>
#include <string_view>

namespace tiltgate {

// The stream to write to (`file` when `path` names one); none, after saying why on stderr as
// `tiltgate COMMAND: cannot write PATH`, when the file cannot be made.
std::ostream* open_csv_output(const std::string& path, std::ofstream& file,
                              std::string_view command);

}  // namespace tiltgate
