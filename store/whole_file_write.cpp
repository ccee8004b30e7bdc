#include "store/whole_file_write.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <span>

#include "store/file_io.h"

namespace tiltgate {

namespace {

// Whose the new file is: the replaced file's owner and group, or for a new file the folder's
// group. Whether it could be given; not an error when not (a user editing a file of their own):
// the file stays the process's, with its mode all the same.
bool give_ownership(int fd, const std::string& path, const std::filesystem::path& folder) {
  struct stat old {};
  if (::stat(path.c_str(), &old) == 0) return ::fchown(fd, old.st_uid, old.st_gid) == 0;
  struct stat folder_stat {};
  return ::stat(folder.c_str(), &folder_stat) == 0 &&
         ::fchown(fd, static_cast<uid_t>(-1), folder_stat.st_gid) == 0;
}

}  // namespace

Expected<Done, std::string> write_whole_file(const std::string& path, std::string_view text,
                                             mode_t mode, FileMode rule) {
  namespace fs = std::filesystem;
  const fs::path target(path);
  const fs::path folder = target.has_parent_path() ? target.parent_path() : fs::path(".");
  std::string temporary = (folder / ("." + target.filename().string() + ".XXXXXX")).string();
  store::UniqueFd fd(::mkostemp(temporary.data(), O_CLOEXEC));
  if (!fd.valid()) return Unexpected(store::errno_text("cannot write a new file in", folder));
  const auto fail = [&temporary](std::string error) -> Expected<Done, std::string> {
    ::unlink(temporary.c_str());
    return Unexpected(std::move(error));
  };
  struct stat old {};
  if (rule == FileMode::keep_old && ::stat(path.c_str(), &old) == 0) mode = old.st_mode & 07777;
  if (::fchmod(fd.get(), mode) != 0)
    return fail(store::errno_text("cannot set the mode of", temporary));
  give_ownership(fd.get(), path, folder);
  const std::span<const std::uint8_t> bytes(reinterpret_cast<const std::uint8_t*>(text.data()),
                                            text.size());
  if (auto written = store::write_all(fd.get(), bytes, temporary); !written)
    return fail(written.error());
  if (auto synced = store::sync_file(fd.get(), temporary); !synced) return fail(synced.error());
  fd.reset();
  if (::rename(temporary.c_str(), path.c_str()) != 0)
    return fail(store::errno_text("cannot rename the new file to", target));
  return store::sync_directory(folder);
}

}  // namespace tiltgate
