// The users file (accounts/users_file.h): reading it with errors at their line, the edits of
// `tiltgate user`, checking a login's password, and writing it back.
#include <doctest/doctest.h>
#include <fmt/format.h>
#include <sys/stat.h>

#include <fstream>
#include <optional>
#include <sstream>
#include <string>

#include "accounts/password_hash.h"
#include "accounts/users_file.h"
#include "unit/support/scratch_dir.h"

using namespace tiltgate;

namespace {

// A hash made once with hash_password() (argon2id, 3 passes, 19 MiB), so that a test of the
// parser costs no hashing.
constexpr const char* kAliceHash =
    "$argon2id$v=19$m=19456,t=3,p=1$BDKsJoVMct6NfHxHnSrb6A$F+4ckCt+viMFhnJTTU6+C2n6H+Xw6wU7Mfjgq333NU0";

// The skipped lines' errors, one a line.
std::string error_of(std::string_view text) {
  const UsersFile file = UsersFile::parse(text, "users");
  REQUIRE_FALSE(file.skipped().empty());
  return fmt::format("{}", fmt::join(file.skipped(), "\n"));
}

std::string read_file(const std::string& path) {
  std::ifstream in(path);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

}  // namespace

TEST_CASE("a users file holds accounts, comments and blank lines") {
  const std::string text = std::string("# the console's accounts\n\nalice:admin:") + kAliceHash +
                           "\n  bob:viewer:" + kAliceHash + "  \r\n# end\n";
  auto file = std::optional(UsersFile::parse(text, "users"));
  CHECK(file->skipped().empty());
  REQUIRE(file->accounts().size() == 2);
  CHECK(file->accounts()[0].name == "alice");
  CHECK(file->accounts()[0].role == Role::admin);
  CHECK(file->accounts()[0].hash == kAliceHash);
  CHECK(file->find("bob")->role == Role::viewer);
  CHECK(file->find("carol") == nullptr);
}

TEST_CASE("each wrong line of a users file is skipped with an error at its line number") {
  const std::string hash = kAliceHash;
  CHECK(error_of("# ok\nalice:admin\n") == "users:2: expected NAME:ROLE:HASH (an account made by "
                                           "`tiltgate user add`) (no login for alice until the "
                                           "line is fixed or removed)");
  CHECK(error_of("alice:boss:" + hash + "\n") ==
        "users:1: alice: role \"boss\" is not viewer, operator or admin (no login for alice "
        "until the line is fixed or removed)");
  CHECK(error_of("\n\nal ice:admin:" + hash + "\n").starts_with("users:3: user name \"al ice\""));
  CHECK(error_of(":admin:" + hash).starts_with("users:1: user name \"\""));
  CHECK(error_of(std::string(65, 'a') + ":admin:" + hash).starts_with("users:1: user name"));
  CHECK(error_of("alice:admin:" + hash + "\nalice:viewer:" + hash + "\n") ==
        "users:2: alice: a second account of that name (no login for alice until the line is "
        "fixed or removed)");
  // Two wrong lines: both said, one a line.
  CHECK(error_of("x\ny\n") == "users:1: expected NAME:ROLE:HASH (an account made by `tiltgate "
                              "user add`)\nusers:2: expected NAME:ROLE:HASH (an account made by "
                              "`tiltgate user add`)");
}

TEST_CASE("a malformed line leaves the other accounts, and its own name has no account") {
  const std::string hash = kAliceHash;
  const UsersFile file = UsersFile::parse("alice:admin:" + hash + "\nbob:viewer:" + hash +
                                              "\nbob:boss:" + hash + "\ngarbage\ncarol:operator:" +
                                              hash + "\ndave:admin:not-a-hash\n",
                                          "users");
  REQUIRE(file.accounts().size() == 2);
  CHECK(file.find("alice")->role == Role::admin);
  CHECK(file.find("carol")->role == Role::operator_);
  // bob's second line is malformed: which of the two was meant cannot be told, so neither.
  CHECK(file.find("bob") == nullptr);
  CHECK(file.find("dave") == nullptr);
  REQUIRE(file.skipped().size() == 3);
  CHECK(file.skipped()[0].starts_with("users:3: bob: role \"boss\""));
  CHECK(file.skipped()[1].starts_with("users:4: expected NAME:ROLE:HASH"));
  CHECK(file.skipped()[2].starts_with("users:6: dave: the third field is not an argon2id hash"));
  // A name refused once stays refused, also on a later well-formed line.
  const UsersFile later =
      UsersFile::parse("erin:boss:" + hash + "\nerin:admin:" + hash + "\n", "users");
  CHECK(later.accounts().empty());
  CHECK(later.skipped().size() == 2);
}

TEST_CASE("a password written in clear in the users file is refused without being repeated") {
  const std::string error = error_of("alice:admin:Tr0ub4dor&3\n");
  CHECK(error.starts_with("users:1: alice: the third field is not an argon2id hash"));
  CHECK(error.find("Tr0ub4dor") == std::string::npos);
  const std::string no_role = error_of("Tr0ub4dor&3\n");
  CHECK(no_role.find("Tr0ub4dor") == std::string::npos);
}

TEST_CASE("a missing users file is an error that says so") {
  auto file = UsersFile::load("/nonexistent/tiltgate/users");
  REQUIRE_FALSE(file.has_value());
  CHECK(file.error().starts_with(
      "/nonexistent/tiltgate/users: cannot read the users file: No such file or directory"));
}

TEST_CASE("added, its password changed and removed: each account verifies its own password") {
  test::ScratchDir dir("tiltgate-users");
  const std::string path = dir.path("users");
  UsersFile file;
  REQUIRE(file.add("alice", Role::admin, "alice-pw").has_value());
  REQUIRE(file.add("bob", Role::viewer, "bob-pw").has_value());
  REQUIRE(file.save(path).has_value());

  auto loaded = UsersFile::load(path);
  REQUIRE(loaded.has_value());
  CHECK(loaded->verify("alice", "alice-pw") == Role::admin);
  CHECK(loaded->verify("bob", "bob-pw") == Role::viewer);

  REQUIRE(loaded->set_password("alice", "new-pw").has_value());
  REQUIRE(loaded->set_role("bob", Role::operator_).has_value());
  REQUIRE(loaded->save(path).has_value());
  auto changed = UsersFile::load(path);
  REQUIRE(changed.has_value());
  CHECK(changed->verify("alice", "new-pw") == Role::admin);
  CHECK_FALSE(changed->verify("alice", "alice-pw").has_value());
  CHECK(changed->find("bob")->role == Role::operator_);

  REQUIRE(changed->remove("bob").has_value());
  REQUIRE(changed->save(path).has_value());
  auto removed = UsersFile::load(path);
  REQUIRE(removed.has_value());
  CHECK(removed->accounts().size() == 1);
  CHECK_FALSE(removed->verify("bob", "bob-pw").has_value());
  // No password in clear, ever.
  const std::string text = read_file(path);
  CHECK(text.find("-pw") == std::string::npos);
}

TEST_CASE("a wrong password and an unknown user are both refused") {
  UsersFile file;
  REQUIRE(file.add("alice", Role::operator_, "alice-pw").has_value());
  CHECK_FALSE(file.verify("alice", "Alice-pw").has_value());
  CHECK_FALSE(file.verify("alice", "").has_value());
  CHECK_FALSE(file.verify("mallory", "alice-pw").has_value());
  CHECK_FALSE(file.verify("", "").has_value());
}

TEST_CASE("an edit that cannot be made says why and changes nothing") {
  UsersFile file;
  REQUIRE(file.add("alice", Role::admin, "alice-pw").has_value());
  CHECK(file.add("alice", Role::viewer, "other").error().starts_with(
      "an account named alice exists already"));
  CHECK(file.add("bob", Role::viewer, "").error() == "an empty password is refused");
  CHECK(file.add("b:ob", Role::viewer, "pw").error().starts_with("user name \"b:ob\""));
  CHECK(file.set_password("alice", "").error() == "an empty password is refused");
  CHECK(file.set_password("bob", "pw").error() == "no account named bob");
  CHECK(file.remove("bob").error() == "no account named bob");
  CHECK(file.accounts().size() == 1);
  CHECK(file.verify("alice", "alice-pw") == Role::admin);
}

TEST_CASE("an edit keeps the file's comments and blank lines where they were") {
  const std::string text = std::string("# plant accounts\nalice:admin:") + kAliceHash +
                           "\n\n# night shift\nbob:viewer:" + kAliceHash + "\n";
  auto file = std::optional(UsersFile::parse(text, "users"));
  REQUIRE(file->set_role("alice", Role::operator_).has_value());
  REQUIRE(file->remove("bob").has_value());
  CHECK(file->text() ==
        std::string("# plant accounts\nalice:operator:") + kAliceHash + "\n\n# night shift\n");
}

TEST_CASE("the users file is written with mode 0640, whatever the umask") {
  test::ScratchDir dir("tiltgate-users");
  const std::string path = dir.path("users");
  const mode_t old_umask = ::umask(0);
  auto saved = UsersFile::parse(std::string("alice:admin:") + kAliceHash, "users").save(path);
  ::umask(old_umask);
  REQUIRE(saved.has_value());
  struct stat written {};
  REQUIRE(::stat(path.c_str(), &written) == 0);
  CHECK((written.st_mode & 07777) == 0640);
  // Nothing left beside it: the temporary file was renamed.
  CHECK(std::distance(std::filesystem::directory_iterator(dir.path("")),
                      std::filesystem::directory_iterator()) == 1);
}
