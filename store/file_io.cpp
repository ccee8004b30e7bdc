#include "store/file_io.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <system_error>

namespace tiltgate::store {

UniqueFd& UniqueFd::operator=(UniqueFd&& other) noexcept {
  if (this != &other) {
    reset();
    fd_ = other.release();
  }
  return *this;
}

UniqueFd::~UniqueFd() { reset(); }

int UniqueFd::release() {
  const int fd = fd_;
  fd_ = -1;
  return fd;
}

void UniqueFd::reset() {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
}

std::string errno_text(const std::string& what, const std::filesystem::path& path) {
  return what + " " + path.string() + ": " + std::strerror(errno);
}

Expected<UniqueFd, std::string> open_file(const std::filesystem::path& path, int flags) {
  const int fd = ::open(path.c_str(), flags | O_CLOEXEC, 0644);
  if (fd < 0) return Unexpected(errno_text("cannot open", path));
  return UniqueFd(fd);
}

Expected<Done, std::string> write_all(int fd, std::span<const std::uint8_t> bytes,
                                      const std::filesystem::path& path) {
  while (!bytes.empty()) {
    const ssize_t n = ::write(fd, bytes.data(), bytes.size());
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return Unexpected(errno_text("cannot write", path));
    bytes = bytes.subspan(static_cast<std::size_t>(n));
  }
  return Done{};
}

Expected<std::size_t, std::string> read_at(int fd, std::span<std::uint8_t> out,
                                           std::uint64_t offset,
                                           const std::filesystem::path& path) {
  std::size_t done = 0;
  while (done < out.size()) {
    const ssize_t n =
        ::pread(fd, out.data() + done, out.size() - done, static_cast<off_t>(offset + done));
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) return Unexpected(errno_text("cannot read", path));
    if (n == 0) break;
    done += static_cast<std::size_t>(n);
  }
  return done;
}

Expected<std::vector<std::uint8_t>, std::string> read_whole(const std::filesystem::path& path) {
  auto fd = open_file(path, O_RDONLY);
  if (!fd) return Unexpected(fd.error());
  std::vector<std::uint8_t> bytes;
  std::uint8_t chunk[65536];
  while (true) {
    auto n = read_at(fd->get(), chunk, bytes.size(), path);
    if (!n) return Unexpected(n.error());
    bytes.insert(bytes.end(), chunk, chunk + *n);
    if (*n < sizeof chunk) return bytes;
  }
}

Expected<Done, std::string> sync_file(int fd, const std::filesystem::path& path) {
  if (::fdatasync(fd) != 0) return Unexpected(errno_text("cannot sync", path));
  return Done{};
}

Expected<Done, std::string> sync_directory(const std::filesystem::path& dir) {
  auto fd = open_file(dir, O_RDONLY | O_DIRECTORY);
  if (!fd) return Unexpected(fd.error());
  if (::fsync(fd->get()) != 0) return Unexpected(errno_text("cannot sync", dir));
  return Done{};
}

Expected<Done, std::string> truncate_file(const std::filesystem::path& path, std::uint64_t size) {
  auto fd = open_file(path, O_WRONLY);
  if (!fd) return Unexpected(fd.error());
  if (::ftruncate(fd->get(), static_cast<off_t>(size)) != 0) {
    return Unexpected(errno_text("cannot truncate", path));
  }
  return sync_file(fd->get(), path);
}

Expected<Done, std::string> replace_file(const std::filesystem::path& path,
                                         std::span<const std::uint8_t> bytes) {
  std::filesystem::path temporary = path;
  temporary += ".tmp";
  {
    auto fd = open_file(temporary, O_WRONLY | O_CREAT | O_TRUNC);
    if (!fd) return Unexpected(fd.error());
    if (auto written = write_all(fd->get(), bytes, temporary); !written) return written;
    if (auto synced = sync_file(fd->get(), temporary); !synced) return synced;
  }
  if (::rename(temporary.c_str(), path.c_str()) != 0) {
    return Unexpected(errno_text("cannot rename to", path));
  }
  return sync_directory(path.parent_path());
}

Expected<std::optional<std::string>, std::string> clear_way_for_file(
    const std::filesystem::path& path) {
  namespace fs = std::filesystem;
  std::error_code error;
  if (fs::symlink_status(path, error).type() != fs::file_type::directory)
    return std::optional<std::string>{};
  const std::string name = path.filename().string();
  if (fs::is_empty(path, error) && !error && fs::remove(path, error))
    return std::optional<std::string>(name + ": an empty directory in the file's place, removed");
  for (int n = 1; n < 100; ++n) {
    fs::path aside = path;
    aside += n == 1 ? std::string(".moved-aside") : ".moved-aside." + std::to_string(n);
    if (fs::symlink_status(aside, error).type() != fs::file_type::not_found) continue;
    fs::rename(path, aside, error);
    if (error) break;
    return std::optional<std::string>(name + ": a directory in the file's place, moved to " +
                                      aside.filename().string());
  }
  return Unexpected(path.string() + " is a directory, not the store's file, and cannot be moved " +
                    "aside" + (error ? ": " + error.message() : std::string()));
}

Expected<UniqueFd, std::string> lock_directory(const std::filesystem::path& dir) {
  const std::filesystem::path path = dir / "lock";
  auto fd = open_file(path, O_RDWR | O_CREAT);
  if (!fd) return Unexpected(fd.error());
  if (::flock(fd->get(), LOCK_EX | LOCK_NB) != 0) {
    if (errno == EWOULDBLOCK)
      return Unexpected(dir.string() +
                        " is in use by another tiltgate (give each its own state_dir)");
    return Unexpected(errno_text("cannot lock", path));
  }
  return std::move(*fd);
}

}  // namespace tiltgate::store
