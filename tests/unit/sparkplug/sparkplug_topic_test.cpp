// The Sparkplug topic namespace (sparkplug/topic.h): topics built and parsed, ids checked.
#include <doctest/doctest.h>

#include "sparkplug/topic.h"

using namespace tiltgate::sparkplug;

TEST_CASE("tck-id-topics-nbirth-topic, -dbirth-topic: node and device topics are spBv1.0/group/TYPE/node[/device]") {
  CHECK(node_topic(MessageType::NBIRTH, "plant", "gw1") == "spBv1.0/plant/NBIRTH/gw1");
  CHECK(node_topic(MessageType::NDEATH, "plant", "gw1") == "spBv1.0/plant/NDEATH/gw1");
  CHECK(device_topic(MessageType::DDATA, "plant", "gw1", "boom") == "spBv1.0/plant/DDATA/gw1/boom");
  CHECK(state_topic("scada") == "spBv1.0/STATE/scada");
}

TEST_CASE("every message type's topic parses back into its parts") {
  for (MessageType type :
       {MessageType::NBIRTH, MessageType::NDATA, MessageType::NDEATH, MessageType::NCMD}) {
    const Topic topic{type, "plant", "gw1", ""};
    CAPTURE(to_string(topic));
    CHECK(parse_topic(to_string(topic)).value() == topic);
  }
  for (MessageType type :
       {MessageType::DBIRTH, MessageType::DDATA, MessageType::DDEATH, MessageType::DCMD}) {
    const Topic topic{type, "plant", "gw1", "boom-left"};
    CAPTURE(to_string(topic));
    CHECK(parse_topic(to_string(topic)).value() == topic);
  }
  CHECK(parse_topic("spBv1.0/STATE/scada").value() == Topic{MessageType::STATE, "", "scada", ""});
}

TEST_CASE("tck-id-topic-structure-namespace-device-id-associated-message-types: a device id only with D* types") {
  CHECK_FALSE(parse_topic("spBv1.0/plant/DDATA/gw1").has_value());
  CHECK_FALSE(parse_topic("spBv1.0/plant/NDATA/gw1/boom").has_value());
  CHECK_FALSE(parse_topic("spBv1.0/STATE/a/b").has_value());
}

TEST_CASE("another namespace, an unknown type or an empty level is not a Sparkplug B topic") {
  CHECK_FALSE(parse_topic("spAv1.0/plant/NDATA/gw1").has_value());
  CHECK_FALSE(parse_topic("tiltgate/demo/boom/state").has_value());
  CHECK(parse_topic("spBv1.0/plant/NFOO/gw1").error().find("NFOO") != std::string::npos);
  CHECK_FALSE(parse_topic("spBv1.0//NDATA/gw1").has_value());
  CHECK_FALSE(parse_topic("spBv1.0/plant/DDATA/gw1/").has_value());
}

TEST_CASE("tck-id-topic-structure-namespace-valid-group-id, -edge-node-id, -device-id: no '+', '#' or '/'") {
  CHECK_FALSE(check_id("group_id", "plant north").has_value());
  CHECK_FALSE(check_id("group_id", "Grüße").has_value());  // any UTF-8
  CHECK(check_id("group_id", "").value() == "group_id is empty");
  CHECK(check_id("edge_node_id", "gw+1").has_value());
  CHECK(check_id("edge_node_id", "gw#").has_value());
  CHECK(check_id("device_id", "boom/left").value().find("'+', '#' or '/'") != std::string::npos);
  CHECK(check_id("device_id", std::string_view("a\0b", 3)).has_value());
  CHECK(check_id("device_id", "\xC3").has_value());          // cut short
  CHECK(check_id("device_id", "\xC0\xAF").has_value());      // an overlong '/'
  CHECK(check_id("device_id", "\xED\xA0\x80").has_value());  // a surrogate
}
