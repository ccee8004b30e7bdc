// The few POSIX file operations the store needs, with errors as values: a descriptor that
// closes itself, whole writes and reads, fsync of a file and of a directory (which makes a
// created, renamed or removed name durable), and replacing a small file atomically.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "driver/expected.h"

namespace tiltgate::store {

class UniqueFd {
 public:
  UniqueFd() = default;
  explicit UniqueFd(int fd) : fd_(fd) {}
  UniqueFd(UniqueFd&& other) noexcept : fd_(other.release()) {}
  UniqueFd& operator=(UniqueFd&& other) noexcept;
  UniqueFd(const UniqueFd&) = delete;
  UniqueFd& operator=(const UniqueFd&) = delete;
  ~UniqueFd();

  int get() const { return fd_; }
  bool valid() const { return fd_ >= 0; }
  int release();
  void reset();

 private:
  int fd_ = -1;
};

// "what PATH: strerror(errno)"
std::string errno_text(const std::string& what, const std::filesystem::path& path);

// flags as for open(2); O_CLOEXEC is added, and 0644 for a created file.
Expected<UniqueFd, std::string> open_file(const std::filesystem::path& path, int flags);
Expected<Done, std::string> write_all(int fd, std::span<const std::uint8_t> bytes,
                                      const std::filesystem::path& path);
// Reads up to out.size() bytes at `offset`; fewer only at the end of the file.
Expected<std::size_t, std::string> read_at(int fd, std::span<std::uint8_t> out,
                                           std::uint64_t offset, const std::filesystem::path& path);
Expected<std::vector<std::uint8_t>, std::string> read_whole(const std::filesystem::path& path);
Expected<Done, std::string> sync_file(int fd, const std::filesystem::path& path);
Expected<Done, std::string> sync_directory(const std::filesystem::path& dir);
// Cuts the file to `size` bytes, durably.
Expected<Done, std::string> truncate_file(const std::filesystem::path& path, std::uint64_t size);
// Writes `bytes` to PATH.tmp, syncs it, renames it over PATH and syncs the directory: after a
// crash PATH holds either its old or its new content, whole.
Expected<Done, std::string> replace_file(const std::filesystem::path& path,
                                         std::span<const std::uint8_t> bytes);
// Locks the directory for this process (flock on its `lock` file, made if missing) while the
// descriptor is open: a second gateway given the same state_dir is told so.
Expected<UniqueFd, std::string> lock_directory(const std::filesystem::path& dir);
// Makes room for the file PATH when a directory stands in its place (made by hand, a restore
// gone wrong), which would stop every open, write and rename of it: an empty one is removed
// (nothing of anyone's is in it), any other is renamed to PATH.moved-aside (.2, .3, ...), its
// content kept for whoever put it there. What was done, for the log; none when the way was
// clear. An error when it could not be done.
Expected<std::optional<std::string>, std::string> clear_way_for_file(
    const std::filesystem::path& path);

}  // namespace tiltgate::store
