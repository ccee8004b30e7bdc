// The console's roles (accounts/role.h): their names in the users file and on the command line,
// and their order.
#include <doctest/doctest.h>

#include "accounts/role.h"

using tiltgate::parse_role;
using tiltgate::Role;
using tiltgate::role_name;

TEST_CASE("the roles are named viewer, operator and admin, and read back from those names") {
  CHECK(role_name(Role::viewer) == "viewer");
  CHECK(role_name(Role::operator_) == "operator");
  CHECK(role_name(Role::admin) == "admin");
  for (Role role : {Role::viewer, Role::operator_, Role::admin})
    CHECK(parse_role(role_name(role)) == role);
}

TEST_CASE("a role name is exact: no other spelling, case or the C++ name is a role") {
  CHECK_FALSE(parse_role("Admin").has_value());
  CHECK_FALSE(parse_role("operator_").has_value());
  CHECK_FALSE(parse_role("").has_value());
  CHECK_FALSE(parse_role("root").has_value());
}

TEST_CASE("each role may do all that the one before it may") {
  CHECK(Role::viewer < Role::operator_);
  CHECK(Role::operator_ < Role::admin);
}
