// An apply's confirmation window (console/confirm_window.h) on files in a scratch folder: what
// an apply writes, when a confirm is taken, a rollback at the deadline and at start-up, and a
// second apply's rollback target. The gateway's reload is a counter here.
#include <doctest/doctest.h>

#include <unistd.h>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include "audit/audit_trail.h"
#include "console/confirm_window.h"

using namespace tiltgate;

namespace {

struct Folder {
  std::filesystem::path path;
  std::string config;
  Folder() {
    char name[] = "/tmp/tiltgate-confirm-XXXXXX";
    path = ::mkdtemp(name);
    config = (path / "gateway.toml").string();
    write(config, "# served\n");
  }
  ~Folder() { std::filesystem::remove_all(path); }
  static void write(const std::string& file, const std::string& text) {
    std::ofstream(file) << text;
  }
  static std::string read(const std::string& file) {
    std::ifstream in(file);
    std::stringstream text;
    text << in.rdbuf();
    return text.str();
  }
};

PendingApply due_in(std::int64_t seconds, std::string changes = "sensors changed: boom") {
  const auto now = std::chrono::duration_cast<std::chrono::seconds>(
      std::chrono::system_clock::now().time_since_epoch());
  return PendingApply{now.count() + seconds, int(seconds), "bob", std::move(changes)};
}

// Polls up to 10 s: the window's thread acts on its own.
template <class Condition>
bool eventually(Condition condition) {
  for (int i = 0; i < 1000; ++i) {
    if (condition()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return condition();
}

std::vector<AuditRecord> records_of(const AuditTrail& trail, const std::string& setting) {
  AuditTrail::Filter filter;
  filter.setting = setting;
  return trail.recent(filter);
}

}  // namespace

TEST_CASE("confirm window: an apply keeps the served file, writes the new one and the window") {
  Folder folder;
  AuditTrail trail("");
  ConfirmWindow window(folder.config, &trail, [] {});
  REQUIRE(window.apply("# applied\n", due_in(60), 1));
  CHECK(Folder::read(folder.config) == "# applied\n");
  CHECK(Folder::read(folder.config + ".previous") == "# served\n");
  const auto on_disk = read_pending(folder.config);
  REQUIRE(on_disk);
  CHECK(on_disk->user == "bob");
  CHECK(on_disk->changes == "sensors changed: boom");
  REQUIRE(window.pending());
}

TEST_CASE("confirm window: FILE.previous takes the served file's mode, whatever an earlier one had") {
  Folder folder;
  std::filesystem::permissions(folder.config, std::filesystem::perms(0644));
  Folder::write(folder.config + ".previous", "# older\n");
  std::filesystem::permissions(folder.config + ".previous", std::filesystem::perms(0600));
  AuditTrail trail("");
  ConfirmWindow window(folder.config, &trail, [] {});
  REQUIRE(window.apply("# applied\n", due_in(60), 1));
  CHECK(std::filesystem::status(folder.config).permissions() == std::filesystem::perms(0644));
  CHECK(std::filesystem::status(folder.config + ".previous").permissions() ==
        std::filesystem::perms(0644));
}

TEST_CASE("confirm window: a confirm is refused until the gateway loaded the applied file") {
  Folder folder;
  AuditTrail trail("");
  ConfirmWindow window(folder.config, &trail, [] {});
  CHECK(window.confirm("bob", 5).error() == "no applied configuration awaits confirmation");
  REQUIRE(window.apply("# applied\n", due_in(60), 3));
  const auto early = window.confirm("carl", 3);
  REQUIRE_FALSE(early);
  CHECK(early.error().find("has not loaded the applied configuration") != std::string::npos);
  const auto confirmed = window.confirm("carl", 4);
  REQUIRE(confirmed);
  CHECK(confirmed->user == "bob");
  CHECK_FALSE(window.pending());
  CHECK_FALSE(std::filesystem::exists(folder.config + ".pending"));
  CHECK(Folder::read(folder.config) == "# applied\n");
  const auto records = records_of(trail, "config confirm");
  REQUIRE(records.size() == 1);
  CHECK(records[0].origin.who == "carl");
  CHECK(records[0].new_value == "sensors changed: boom");
}

TEST_CASE("confirm window: unconfirmed at the deadline, the previous file is back and reloaded") {
  Folder folder;
  AuditTrail trail("");
  std::atomic<int> reloads{0};
  ConfirmWindow window(folder.config, &trail, [&] { ++reloads; });
  REQUIRE(window.apply("# applied\n", due_in(1), 1));
  CHECK(eventually([&] { return reloads == 1; }));
  CHECK(Folder::read(folder.config) == "# served\n");
  CHECK_FALSE(std::filesystem::exists(folder.config + ".pending"));
  CHECK_FALSE(window.pending());
  const auto records = records_of(trail, "config rollback");
  REQUIRE(records.size() == 1);
  CHECK(records[0].origin.who == "bob");
  CHECK(records[0].old_value == "sensors changed: boom");
  CHECK(records[0].result == "ok: not confirmed within 1 s, previous file restored");
}

TEST_CASE("confirm window: a second apply restarts the window and keeps the last confirmed file") {
  Folder folder;
  AuditTrail trail("");
  std::atomic<int> reloads{0};
  ConfirmWindow window(folder.config, &trail, [&] { ++reloads; });
  REQUIRE(window.apply("# first\n", due_in(60), 1));
  REQUIRE(window.apply("# second\n", due_in(1), 2));
  CHECK(Folder::read(folder.config + ".previous") == "# served\n");
  CHECK(eventually([&] { return reloads == 1; }));
  CHECK(Folder::read(folder.config) == "# served\n");
}

TEST_CASE("confirm window: across a restart, a due window rolls back before the file is loaded") {
  Folder folder;
  {
    AuditTrail trail("");
    ConfirmWindow window(folder.config, &trail, [] {});
    REQUIRE(window.apply("# applied\n", due_in(3600), 1));
  }  // the gateway stops: the window stays on disk
  CHECK_FALSE(ConfirmWindow::roll_back_if_due(folder.config));  // not due yet
  CHECK(Folder::read(folder.config) == "# applied\n");
  REQUIRE(write_pending(folder.config, due_in(-5)));
  const auto rolled = ConfirmWindow::roll_back_if_due(folder.config);
  REQUIRE(rolled);
  CHECK(Folder::read(folder.config) == "# served\n");
  AuditTrail trail("");
  ConfirmWindow window(folder.config, &trail, [] {});
  window.resume(rolled);
  CHECK(records_of(trail, "config rollback")[0].result ==
        "ok: not confirmed in time, restored at start-up");
  CHECK_FALSE(window.pending());
}

TEST_CASE("confirm window: a restart during the window waits for the rest of it") {
  Folder folder;
  {
    AuditTrail trail("");
    ConfirmWindow window(folder.config, &trail, [] {});
    REQUIRE(window.apply("# applied\n", due_in(2), 1));
  }
  AuditTrail trail("");
  std::atomic<int> reloads{0};
  ConfirmWindow window(folder.config, &trail, [&] { ++reloads; });
  window.resume(std::nullopt);
  REQUIRE(window.pending());
  CHECK(eventually([&] { return reloads == 1; }));
  CHECK(Folder::read(folder.config) == "# served\n");
}

TEST_CASE("confirm window: a marker that cannot be read counts as due") {
  Folder folder;
  Folder::write(folder.config + ".previous", "# served before\n");
  Folder::write(folder.config + ".pending", "not json");
  CHECK(ConfirmWindow::roll_back_if_due(folder.config));
  CHECK(Folder::read(folder.config) == "# served before\n");
}
