"""Decodes a Sparkplug B payload with protoc's Python output of sparkplug/sparkplug_b.proto
(Debian's python3-protobuf), independently of the gateway's protobuf-c code, and prints every
field it finds, one line each, for tests/unit/sparkplug_independent_decoder_test.cpp.

Usage: /usr/bin/python3 sparkplug_decode.py DIR_WITH_sparkplug_b_pb2 PAYLOAD_FILE
"""
import sys

sys.path.insert(0, sys.argv[1])
import sparkplug_b_pb2  # noqa: E402  (generated into sys.argv[1] by the test)


def value(message):
    which = message.WhichOneof("value")
    if which is None:
        return "null" if message.is_null else "none"
    return "%s=%r" % (which, getattr(message, which))


def optional(message, field):
    return repr(getattr(message, field)) if message.HasField(field) else "-"


payload = sparkplug_b_pb2.Payload()
with open(sys.argv[2], "rb") as f:
    payload.ParseFromString(f.read())
print("timestamp", optional(payload, "timestamp"))
print("seq", optional(payload, "seq"))
for m in payload.metrics:
    line = "metric name=%s alias=%s timestamp=%s datatype=%s historical=%s %s" % (
        optional(m, "name"), optional(m, "alias"), optional(m, "timestamp"),
        optional(m, "datatype"), optional(m, "is_historical"), value(m))
    if m.HasField("properties"):
        properties = m.properties
        line += " properties=" + ",".join(
            "%s:%d:%s" % (k, v.type, value(v)) for k, v in zip(properties.keys, properties.values))
    print(line)
