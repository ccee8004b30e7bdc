// A directory of its own under /tmp for tests that load files (map files, device profiles),
// removed afterwards.
#pragma once

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>

namespace tiltgate::test {

class ScratchDir {
 public:
  explicit ScratchDir(std::string_view prefix = "tiltgate-test") {
    static int counter = 0;
    root_ = std::filesystem::temp_directory_path() /
            (std::string(prefix) + "-" + std::to_string(::getpid()) + "-" +
             std::to_string(counter++));
    std::filesystem::create_directories(root_);
  }
  ~ScratchDir() {
    std::error_code ignored;
    std::filesystem::remove_all(root_, ignored);
  }
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;

  std::string path(const std::string& name) const { return (root_ / name).string(); }
  // Writes `text` to `name` (folders created) and returns its path.
  std::string write(const std::string& name, std::string_view text) const {
    const std::filesystem::path file = root_ / name;
    std::filesystem::create_directories(file.parent_path());
    std::ofstream(file) << text;
    return file.string();
  }

 private:
  std::filesystem::path root_;
};

}  // namespace tiltgate::test
