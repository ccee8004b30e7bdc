// bdSeq across restarts (sparkplug/bd_seq_file.h): a real file in a scratch directory, replaced
// atomically, read back; what a missing or damaged file gives.
#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>

#include "sparkplug/bd_seq_file.h"
#include "unit/support/scratch_dir.h"

using namespace tiltgate;
using namespace tiltgate::sparkplug;
using tiltgate::test::ScratchDir;

TEST_CASE("bdSeq file: none on a first start, then what was written, through 255") {
  ScratchDir dir;
  const std::filesystem::path file = dir.path("bdSeq");
  auto first = read_bd_seq(file);
  REQUIRE(first.has_value());
  CHECK_FALSE(first->has_value());
  for (const int value : {0, 1, 17, 255}) {
    CAPTURE(value);
    REQUIRE(write_bd_seq(file, std::uint8_t(value)).has_value());
    auto read = read_bd_seq(file);
    REQUIRE(read.has_value());
    CHECK(*read == std::optional<std::uint8_t>(std::uint8_t(value)));
  }
  // Replaced, not appended to: nothing beside it is left from the writes.
  CHECK_FALSE(std::filesystem::exists(file.string() + ".tmp"));
  std::ifstream in(file);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  CHECK(text == "255\n");
}

TEST_CASE("bdSeq file: a damaged file is an error that names it, never a value") {
  ScratchDir dir;
  for (const char* text : {"", "abc\n", "256\n", "-1\n", "12x\n"}) {
    CAPTURE(text);
    const std::string file = dir.write("bdSeq", text);
    auto read = read_bd_seq(file);
    REQUIRE_FALSE(read.has_value());
    CHECK(read.error().find(file) != std::string::npos);
    CHECK(read.error().find("expected a number 0..255") != std::string::npos);
  }
}

TEST_CASE("bdSeq file: a directory that cannot be written is an error") {
  ScratchDir dir;
  const std::filesystem::path file = dir.path("missing-folder/bdSeq");
  CHECK_FALSE(write_bd_seq(file, 3).has_value());
}
