// A real small disk for the store's disk-fault tests: a tmpfs of a few pages mounted on a
// directory of its own, in a mount namespace of the test's own (so no mount outlives the test,
// whatever its outcome, and nobody else sees it), filled to ENOSPC on demand. Needs root, as CI
// runs; available() is false otherwise, and the tests say so and pass.
#pragma once

#include <doctest/doctest.h>
#include <fcntl.h>
#include <sched.h>
#include <sys/mount.h>
#include <unistd.h>

#include <filesystem>
#include <string>
#include <vector>

namespace tiltgate::test {

class SmallDisk {
 public:
  explicit SmallDisk(std::size_t kib = 256) {
    if (::geteuid() != 0) return;
    // This thread alone moves to a new mount namespace; a private "/" keeps the mount in it.
    if (::unshare(CLONE_NEWNS) != 0 ||
        ::mount(nullptr, "/", nullptr, MS_REC | MS_PRIVATE, nullptr) != 0)
      return;
    std::string pattern = (std::filesystem::temp_directory_path() / "tiltgate-disk-XXXXXX").string();
    if (::mkdtemp(pattern.data()) == nullptr) return;
    root_ = pattern;
    const std::string options = "size=" + std::to_string(kib) + "k";
    mounted_ = ::mount("tmpfs", root_.c_str(), "tmpfs", 0, options.c_str()) == 0;
  }
  ~SmallDisk() {
    if (mounted_) ::umount2(root_.c_str(), MNT_DETACH);
    if (!root_.empty()) ::rmdir(root_.c_str());
  }
  SmallDisk(const SmallDisk&) = delete;
  SmallDisk& operator=(const SmallDisk&) = delete;

  bool available() const { return mounted_; }
  std::filesystem::path path(const std::string& name) const { return root_ / name; }

  // Takes every free block with a filler file: the next write that needs one gets ENOSPC.
  void fill() {
    const int fd = ::open(path("filler").c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
    if (fd < 0) return;
    const std::vector<char> block(4096, 'x');
    while (::write(fd, block.data(), block.size()) > 0) {
    }
    for (std::size_t size = 2048; size > 0; size /= 2)
      while (::write(fd, block.data(), size) > 0) {
      }
    ::close(fd);
  }
  // Room again.
  void free() { std::filesystem::remove(path("filler")); }

 private:
  std::filesystem::path root_;
  bool mounted_ = false;
};

// For a test's first line: true (said, and the test passes) where no tmpfs can be made.
inline bool no_small_disk(const SmallDisk& disk) {
  if (disk.available()) return false;
  MESSAGE("needs root for a tmpfs: skipped");
  return true;
}

}  // namespace tiltgate::test
