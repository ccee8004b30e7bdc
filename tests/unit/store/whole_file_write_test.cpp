// store/whole_file_write.h: a file replaced whole keeps what it should of the old one. The
// users file is always 0640; a configuration keeps its mode, and (as root) its owner and
// group, so root's `tiltgate set --config` leaves the service's file the service's to replace.
#include <doctest/doctest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>

#include "store/whole_file_write.h"
#include "unit/support/scratch_dir.h"

using namespace tiltgate;

namespace {

std::string read_file(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

struct stat stat_of(const std::filesystem::path& path) {
  struct stat st {};
  REQUIRE(::stat(path.c_str(), &st) == 0);
  return st;
}

}  // namespace

TEST_CASE("a file replaced whole with the given mode has it, whatever the old one had") {
  test::ScratchDir dir("whole-file");
  const std::filesystem::path path = dir.write("users", "old\n");
  ::chmod(path.c_str(), 0604);
  REQUIRE(write_whole_file(path.string(), "new\n", 0640, FileMode::given).has_value());
  CHECK(read_file(path) == "new\n");
  CHECK((stat_of(path).st_mode & 07777) == 0640);
}

TEST_CASE("a file replaced whole keeping the old mode keeps it, and a new file gets the given one") {
  test::ScratchDir dir("whole-file");
  const std::filesystem::path path = dir.write("tiltgate.toml", "old\n");
  ::chmod(path.c_str(), 0604);
  REQUIRE(write_whole_file(path.string(), "new\n", 0640, FileMode::keep_old).has_value());
  CHECK(read_file(path) == "new\n");
  CHECK((stat_of(path).st_mode & 07777) == 0604);
  const std::filesystem::path fresh = dir.path("tiltgate.toml.previous");
  REQUIRE(write_whole_file(fresh.string(), "old\n", 0640, FileMode::keep_old).has_value());
  CHECK((stat_of(fresh).st_mode & 07777) == 0640);
  // Nothing left beside them.
  const auto files = std::distance(std::filesystem::directory_iterator(path.parent_path()),
                                   std::filesystem::directory_iterator());
  CHECK(files == 2);
}

TEST_CASE("a file replaced whole keeps its owner and group where the process may give them") {
  test::ScratchDir dir("whole-file");
  const std::filesystem::path path = dir.write("tiltgate.toml", "old\n");
  // As root (the commissioning commands, the package's tests): another owner's file stays
  // theirs. As anyone else the file is the process's own, which it keeps.
  const uid_t owner = ::geteuid() == 0 ? 65534 : ::geteuid();
  const gid_t group = ::geteuid() == 0 ? 65534 : ::getegid();
  REQUIRE(::chown(path.c_str(), owner, group) == 0);
  REQUIRE(write_whole_file(path.string(), "new\n", 0640, FileMode::keep_old).has_value());
  CHECK(stat_of(path).st_uid == owner);
  CHECK(stat_of(path).st_gid == group);
}

TEST_CASE("a file that cannot be replaced is left whole, and the error names the folder") {
  test::ScratchDir dir("whole-file");
  const std::string path = dir.path("missing-folder/tiltgate.toml");
  const auto written = write_whole_file(path, "new\n", 0640, FileMode::keep_old);
  REQUIRE_FALSE(written.has_value());
  CHECK(written.error().find("missing-folder") != std::string::npos);
}
