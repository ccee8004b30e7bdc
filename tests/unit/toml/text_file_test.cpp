// Configuration, map and profile files are read only when they are regular files of at most
// 1 MiB: /dev/zero, a FIFO or a huge file given by mistake gets a clear error at once, never
// a hang or an exhausted memory.
#include <doctest/doctest.h>

#include <sys/stat.h>

#include <string>

#include "toml/text_file.h"
#include "unit/support/scratch_dir.h"

using namespace tiltgate;
using tiltgate::toml_input::kMaxTextFileBytes;
using tiltgate::toml_input::read_text_file;

TEST_CASE("text file: a regular file is read whole") {
  test::ScratchDir dir;
  const std::string path = dir.write("a.toml", "[server]\nport = 502\n");
  const auto text = read_text_file(path);
  REQUIRE(text);
  CHECK(*text == "[server]\nport = 502\n");
}

TEST_CASE("text file: exactly 1 MiB is read, one byte more is refused") {
  test::ScratchDir dir;
  const auto at_limit = read_text_file(dir.write("max.toml", std::string(kMaxTextFileBytes, '#')));
  REQUIRE(at_limit);
  CHECK(at_limit->size() == kMaxTextFileBytes);
  const auto over = read_text_file(dir.write("big.toml", std::string(kMaxTextFileBytes + 1, '#')));
  REQUIRE_FALSE(over);
  CHECK(over.error() == "is 1048577 bytes, more than the 1048576 bytes (1 MiB) a file may have");
}

TEST_CASE("text file: /dev/zero is refused as a character device, not read") {
  const auto zero = read_text_file("/dev/zero");
  REQUIRE_FALSE(zero);
  CHECK(zero.error() == "is a character device, expected a regular file");
}

TEST_CASE("text file: a FIFO is refused at once, not waited on") {
  test::ScratchDir dir;
  const std::string fifo = dir.path("config.fifo");
  REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);
  // Without O_NONBLOCK this call would wait forever for a writer; ctest's time-out fails it.
  const auto text = read_text_file(fifo);
  REQUIRE_FALSE(text);
  CHECK(text.error() == "is a FIFO, expected a regular file");
}

TEST_CASE("text file: a directory and a missing file say so") {
  test::ScratchDir dir;
  const auto folder = read_text_file(dir.path(""));
  REQUIRE_FALSE(folder);
  CHECK(folder.error() == "is a directory, expected a regular file");
  const auto missing = read_text_file(dir.path("nothing.toml"));
  REQUIRE_FALSE(missing);
  CHECK(missing.error() == "cannot open: No such file or directory");
}
