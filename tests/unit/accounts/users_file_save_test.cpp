// The users file is replaced atomically (store/whole_file_write.h): when the new file
// cannot be written, the old one stays whole and nothing is left beside it.
#include <doctest/doctest.h>
#include <sys/mount.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "accounts/users_file.h"
#include "unit/support/scratch_dir.h"
#include "unit/support/small_disk.h"

using namespace tiltgate;

namespace {

const std::string kOldFile =
    "alice:admin:$argon2id$v=19$m=19456,t=3,p=1$BDKsJoVMct6NfHxHnSrb6A$"
    "F+4ckCt+viMFhnJTTU6+C2n6H+Xw6wU7Mfjgq333NU0\n";

std::string read_file(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

std::size_t files_in(const std::filesystem::path& folder) {
  return static_cast<std::size_t>(std::distance(std::filesystem::directory_iterator(folder),
                                                std::filesystem::directory_iterator()));
}

// A users file of 60 accounts (7 KiB, more than the old file's page a truncation would free),
// with kOldFile's hash, so it costs no hashing.
UsersFile many_accounts() {
  std::string text;
  for (int i = 0; i < 60; ++i)
    text += "user" + std::to_string(i) + kOldFile.substr(kOldFile.find(':'));
  auto file = UsersFile::parse(text, "many");
  REQUIRE(file.skipped().empty());
  return file;
}

// many_accounts() saved over kOldFile at `path`: refused, the old file whole, nothing beside it.
void check_save_refused_and_old_file_kept(const std::filesystem::path& path) {
  const std::size_t files_before = files_in(path.parent_path());
  auto saved = many_accounts().save(path.string());
  REQUIRE_FALSE(saved.has_value());
  MESSAGE(saved.error());
  CHECK(read_file(path) == kOldFile);
  CHECK(files_in(path.parent_path()) == files_before);  // no temporary file left
}

}  // namespace

TEST_CASE("a users file in a folder that cannot be written stays as it was") {
  if (::geteuid() != 0) {
    test::ScratchDir dir("tiltgate-users");
    const std::filesystem::path path = dir.write("users", kOldFile);
    ::chmod(dir.path("").c_str(), 0555);
    check_save_refused_and_old_file_kept(path);
    ::chmod(dir.path("").c_str(), 0755);
    return;
  }
  // Root writes in any folder whatever its mode: a read-only file system instead.
  test::SmallDisk disk;
  if (test::no_small_disk(disk)) return;
  const std::filesystem::path path = disk.path("users");
  std::ofstream(path) << kOldFile;
  REQUIRE(::mount(nullptr, disk.path("").c_str(), nullptr, MS_REMOUNT | MS_RDONLY, nullptr) == 0);
  check_save_refused_and_old_file_kept(path);
  ::mount(nullptr, disk.path("").c_str(), nullptr, MS_REMOUNT, nullptr);
}

TEST_CASE("a users file whose replacement finds the disk full stays as it was") {
  test::SmallDisk disk;
  if (test::no_small_disk(disk)) return;
  const std::filesystem::path path = disk.path("users");
  std::ofstream(path) << kOldFile;
  disk.fill();
  check_save_refused_and_old_file_kept(path);
  disk.free();
}

TEST_CASE("a new users file takes its folder's group, a replaced one keeps its owner and group") {
  if (::geteuid() != 0) {
    MESSAGE("needs root to give a file away: skipped");
    return;
  }
  test::ScratchDir dir("tiltgate-users");
  const gid_t group = 65534;  // nogroup: any group but root's
  REQUIRE(::chown(dir.path("").c_str(), 0, group) == 0);
  const std::string path = dir.path("users");
  UsersFile file;
  REQUIRE(file.add("alice", Role::admin, "alice-pw").has_value());
  REQUIRE(file.save(path).has_value());
  struct stat made {};
  REQUIRE(::stat(path.c_str(), &made) == 0);
  CHECK(made.st_gid == group);

  REQUIRE(::chown(path.c_str(), 1, 2) == 0);
  REQUIRE(file.remove("alice").has_value());
  REQUIRE(file.save(path).has_value());
  struct stat replaced {};
  REQUIRE(::stat(path.c_str(), &replaced) == 0);
  CHECK(replaced.st_uid == 1u);
  CHECK(replaced.st_gid == 2u);
  CHECK((replaced.st_mode & 07777) == 0640);
}
