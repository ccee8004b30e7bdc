// A primary host's STATE payload (sparkplug/host_state.h).
#include <doctest/doctest.h>

#include "sparkplug/host_state.h"

using namespace tiltgate::sparkplug;

TEST_CASE("tck-id-host-topic-phid-birth-payload: {\"online\": true, \"timestamp\": ms} is an online host") {
  CHECK(parse_host_state(R"({"online" : true, "timestamp" : 1668114759262})").value() ==
        HostState{true, 1668114759262});
  CHECK(parse_host_state("{\"timestamp\":5,\"online\":false}").value() == HostState{false, 5});
}

TEST_CASE("other keys are ignored, strings with escapes and numbers among them") {
  CHECK(parse_host_state(
            R"({"bdSeq": 3, "name": "a \"quoted\" }", "online": true, "timestamp": 9, "x": null})")
            .value() == HostState{true, 9});
}

TEST_CASE("a STATE that is not the 3.0 JSON is refused with the reason") {
  CHECK(parse_host_state("ONLINE").error() == "a STATE payload is a JSON object");  // Sparkplug 2.2
  CHECK(parse_host_state(R"({"online": true})").error() == "no \"timestamp\" key");
  CHECK(parse_host_state(R"({"timestamp": 1})").error() == "no \"online\" key");
  CHECK(parse_host_state(R"({"online": "true", "timestamp": 1})").has_value() == false);
  CHECK(parse_host_state(R"({"online": 1, "timestamp": 1})").has_value() == false);
  CHECK(parse_host_state(R"({"online": true, "timestamp": -1})").has_value() == false);
  CHECK(parse_host_state(R"({"online": true, "timestamp": 1.5})").has_value() == false);
  CHECK(parse_host_state(R"({"online": true, "timestamp": 1, "n": {"a": 1}})").has_value() ==
        false);
  CHECK(parse_host_state(R"({"online": true, "timestamp": 1} x)").has_value() == false);
  CHECK(parse_host_state(R"({"online": true "timestamp": 1})").has_value() == false);
  CHECK(parse_host_state(R"({"online": true, "timestamp": 1)").has_value() == false);
  CHECK(parse_host_state(R"({"on)").has_value() == false);
  CHECK(parse_host_state(std::string(5000, ' ')).has_value() == false);
}
