#include "toml/text_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fmt/format.h>

namespace tiltgate::toml_input {

namespace {

const char* kind_of(mode_t mode) {
  if (S_ISDIR(mode)) return "a directory";
  if (S_ISFIFO(mode)) return "a FIFO";
  if (S_ISCHR(mode)) return "a character device";
  if (S_ISBLK(mode)) return "a block device";
  if (S_ISSOCK(mode)) return "a socket";
  return "not a regular file";
}

// Closes the descriptor however the read ends.
struct FileDescriptor {
  int fd;
  ~FileDescriptor() {
    if (fd >= 0) ::close(fd);
  }
};

}  // namespace

Expected<std::string, std::string> read_text_file(const std::string& path) {
  // O_NONBLOCK: opening a FIFO for reading would otherwise wait for a writer forever. The
  // file's type is checked on the open descriptor, so it cannot change between check and read.
  FileDescriptor file{::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC)};
  if (file.fd < 0) return Unexpected("cannot open: " + std::string(std::strerror(errno)));
  struct stat info {};
  if (::fstat(file.fd, &info) != 0)
    return Unexpected("cannot read the file: " + std::string(std::strerror(errno)));
  if (!S_ISREG(info.st_mode))
    return Unexpected(fmt::format("is {}, expected a regular file", kind_of(info.st_mode)));
  if (info.st_size > std::int64_t(kMaxTextFileBytes))
    return Unexpected(fmt::format("is {} bytes, more than the {} bytes (1 MiB) a file may have",
                                  info.st_size, kMaxTextFileBytes));
  // Read at most one byte past the limit: a file that grows meanwhile is still bounded.
  std::string text(kMaxTextFileBytes + 1, '\0');
  std::size_t length = 0;
  while (length < text.size()) {
    const ssize_t n = ::read(file.fd, text.data() + length, text.size() - length);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) return Unexpected("cannot read the file: " + std::string(std::strerror(errno)));
    if (n == 0) break;
    length += std::size_t(n);
  }
  if (length > kMaxTextFileBytes)
    return Unexpected(fmt::format("is more than the {} bytes (1 MiB) a file may have",
                                  kMaxTextFileBytes));
  text.resize(length);
  return text;
}

Expected<std::string, std::string> read_toml_file(const std::string& path) {
  auto text = read_text_file(path);
  if (!text) return text;
  if (!path.ends_with(".toml"))
    return Unexpected(std::string(
        "is not named *.toml: only a TOML file is read here, and nothing of another is shown"));
  return text;
}

}  // namespace tiltgate::toml_input
