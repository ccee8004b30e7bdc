// Reading a store's records without opening it (record_store.h): for a command that shows what
// a running gateway keeps (`tiltgate audit`), or keeps after it stopped. Reads only: it cuts
// nothing and moves no cursor, so it is safe beside the gateway appending to the same
// directory; a record being written at that moment (cut short) ends its segment's reading,
// as a torn one would.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "driver/expected.h"
#include "store/record_frame.h"

namespace tiltgate::store {

// Every whole record of the segment files in `dir`, in append order, replayed or not. A
// segment is read up to its first record that is not whole and valid. Fails when `dir` cannot
// be listed or a segment cannot be read.
Expected<std::vector<Record>, std::string> read_records(const std::filesystem::path& dir);

}  // namespace tiltgate::store
