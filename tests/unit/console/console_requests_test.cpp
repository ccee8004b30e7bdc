// The console API's JSON bodies: what is taken, and a one-line reason for what is not.
#include <doctest/doctest.h>

#include "console/bus_actions.h"
#include "console/console_requests.h"

using namespace tiltgate;

TEST_CASE("a login body needs a user and a password, both strings of bounded size") {
  auto ok = parse_login_request(R"({"user": "alice", "password": "s3cret \"x\""})");
  REQUIRE(ok);
  CHECK(ok->user == "alice");
  CHECK(ok->password == "s3cret \"x\"");
  CHECK(parse_login_request("").error() == "the body is not JSON");
  CHECK(parse_login_request("[1]").error() == "the body is not a JSON object");
  CHECK(parse_login_request(R"({"user": "alice"})").error() == "\"password\" is missing");
  CHECK(parse_login_request(R"({"user": 5, "password": "x"})").error() ==
        "\"user\" is not a string");
  const std::string long_name(kMaxUserName + 1, 'a');
  CHECK(parse_login_request(R"({"user": ")" + long_name + R"(", "password": "x"})").error() ==
        "\"user\" is longer than 64 bytes");
  CHECK_FALSE(parse_login_request(R"({"user": "a", "password": "x")"));  // cut short
}

TEST_CASE("a setting body names the setting and a finite number (or a Boolean)") {
  auto filter = parse_setting_request(R"({"setting": "filter", "value": 3})");
  REQUIRE(filter);
  CHECK(filter->setting == "filter");
  CHECK(filter->value == 3);
  CHECK(parse_setting_request(R"({"setting": "zero", "value": true})")->value == 1);
  CHECK(parse_setting_request(R"({"setting": "zero", "value": "3"})").error() ==
        "\"value\" is not a number");
  CHECK(parse_setting_request(R"({"value": 3})").error() == "\"setting\" is missing");
  CHECK_FALSE(parse_setting_request(R"({"setting": "zero", "value": 1e999})"));
}

TEST_CASE("scan and raw bodies: ranges checked") {
  CHECK(parse_scan_request("")->to == 0);
  auto range = parse_scan_request(R"({"from": 5, "to": 20})");
  REQUIRE(range);
  CHECK(range->from == 5);
  CHECK(range->to == 20);
  CHECK(parse_scan_request(R"({"from": 20, "to": 5})").error() == "\"to\" is below \"from\"");
  CHECK_FALSE(parse_scan_request(R"({"from": -1})"));
  auto raw = parse_raw_request(R"({"address": 5, "function": 16, "data": "01 0A"})");
  REQUIRE(raw);
  CHECK(raw->data == "01 0A");
  CHECK(parse_raw_request(R"({"function": 16})").error() == "\"address\" is missing");
  CHECK(parse_raw_request(R"({"address": 1.5, "function": 16})").error() ==
        "\"address\" is not a whole number");
}

TEST_CASE("a configuration body: the text, and a confirmation window of 5 to 3600 s") {
  auto plain = parse_config_text(R"({"text": "[server]\n"})");
  REQUIRE(plain);
  CHECK(plain->confirm_s == 120);
  CHECK(parse_config_text(R"({"text": "", "confirm_s": 30})")->confirm_s == 30);
  CHECK(parse_config_text(R"({"text": "", "confirm_s": 4})").error() ==
        "\"confirm_s\" is 4, expected 5 to 3600 seconds");
  CHECK_FALSE(parse_config_text(R"({"text": "", "confirm_s": 3601})"));
  CHECK(parse_config_text(R"({"text": "", "confirm_s": "60"})").error() ==
        "\"confirm_s\" is not a whole number");
}
