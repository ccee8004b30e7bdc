// [server] allow / write_allow and [http] allow entries, and which peers they let in
// (config/address_allow_list.h).
#include <doctest/doctest.h>

#include <string>
#include <vector>

#include "config/address_allow_list.h"

using namespace tiltgate;

namespace {

AddressAllowList list_of(std::vector<std::string> entries) {
  auto list = AddressAllowList::parse(entries);
  REQUIRE_MESSAGE(list.has_value(), list.error());
  return *list;
}

std::string error_of(std::string entry) {
  const std::vector<std::string> entries{std::move(entry)};
  auto list = AddressAllowList::parse(entries);
  REQUIRE_FALSE(list.has_value());
  return list.error();
}

}  // namespace

TEST_CASE("allow list: none given allows everyone, an empty one nobody") {
  const AddressAllowList everyone;
  CHECK(everyone.allows_everyone());
  CHECK(everyone.allows("10.1.2.3"));
  CHECK(everyone.allows("fe80::1"));
  const AddressAllowList nobody = list_of({});
  CHECK_FALSE(nobody.allows_everyone());
  CHECK_FALSE(nobody.allows("127.0.0.1"));
}

TEST_CASE("allow list: IPv4 addresses and networks, /32 and /0") {
  const AddressAllowList list = list_of({"10.0.0.0/8", "192.168.1.20", "172.16.5.4/32"});
  CHECK(list.allows("10.0.0.1"));
  CHECK(list.allows("10.255.255.255"));
  CHECK_FALSE(list.allows("11.0.0.1"));
  CHECK(list.allows("192.168.1.20"));
  CHECK_FALSE(list.allows("192.168.1.21"));
  CHECK(list.allows("172.16.5.4"));
  CHECK_FALSE(list.allows("172.16.5.5"));
  CHECK_FALSE(list.allows("::1"));
  const AddressAllowList any_v4 = list_of({"0.0.0.0/0"});
  CHECK(any_v4.allows("203.0.113.9"));
  CHECK_FALSE(any_v4.allows("2001:db8::1"));
  CHECK(list_of({"10.1.2.0/23"}).allows("10.1.3.200"));
  CHECK_FALSE(list_of({"10.1.2.0/23"}).allows("10.1.4.1"));
}

TEST_CASE("allow list: IPv6 addresses and networks, /128 and /0") {
  const AddressAllowList list = list_of({"::1", "fd00:1234::/32", "2001:db8::7/128"});
  CHECK(list.allows("::1"));
  CHECK_FALSE(list.allows("::2"));
  CHECK(list.allows("fd00:1234:ffff::1"));
  CHECK_FALSE(list.allows("fd00:1235::1"));
  CHECK(list.allows("2001:db8::7"));
  CHECK_FALSE(list.allows("2001:db8::8"));
  CHECK_FALSE(list.allows("10.0.0.1"));
  const AddressAllowList any = list_of({"::/0"});
  CHECK(any.allows("2001:db8::1"));
}

TEST_CASE("allow list: an IPv4-mapped IPv6 peer matches IPv4 rules") {
  const AddressAllowList list = list_of({"10.0.0.0/8", "192.168.1.20"});
  CHECK(list.allows("::ffff:10.9.8.7"));
  CHECK(list.allows("::ffff:192.168.1.20"));
  CHECK_FALSE(list.allows("::ffff:192.168.1.21"));
  // And the other way round: a mapped rule is the IPv4 address.
  CHECK(list_of({"::ffff:192.168.1.20"}).allows("192.168.1.20"));
}

TEST_CASE("allow list: what is not an address is never allowed by a list") {
  const AddressAllowList list = list_of({"0.0.0.0/0", "::/0"});
  CHECK_FALSE(list.allows("(unknown peer)"));
  CHECK_FALSE(list.allows(""));
}

TEST_CASE("allow list: bad entries are refused with what is wrong") {
  CHECK(error_of("10.0.0.256") == "\"10.0.0.256\": \"10.0.0.256\" is not an IPv4 or IPv6 address");
  CHECK(error_of("plc.local") == "\"plc.local\": \"plc.local\" is not an IPv4 or IPv6 address");
  CHECK(error_of("") == "\"\": \"\" is not an IPv4 or IPv6 address");
  CHECK(error_of("10.0.0.0/33") == "\"10.0.0.0/33\": the prefix length must be 0..32");
  CHECK(error_of("::/129") == "\"::/129\": the prefix length must be 0..128");
  CHECK(error_of("10.0.0.0/") == "\"10.0.0.0/\": the prefix length must be 0..32");
  CHECK(error_of("10.0.0.0/8x") == "\"10.0.0.0/8x\": the prefix length must be 0..32");
  CHECK(error_of("10.0.0.0/-1") == "\"10.0.0.0/-1\": the prefix length must be 0..32");
  CHECK(error_of("10.0.0.1/8").find("bits are set past the /8 prefix") != std::string::npos);
  CHECK(error_of("fd00::1/16").find("bits are set past the /16 prefix") != std::string::npos);
  // The first bad entry is named.
  const std::vector<std::string> entries{"10.0.0.0/8", "bad", "worse"};
  auto list = AddressAllowList::parse(entries);
  REQUIRE_FALSE(list.has_value());
  CHECK(list.error().find("\"bad\"") == 0);
}

TEST_CASE("allow list: the entries are kept as written") {
  CHECK(list_of({"10.0.0.0/8", "::1"}).entries() == std::vector<std::string>{"10.0.0.0/8", "::1"});
  CHECK(AddressAllowList{}.entries().empty());
}
