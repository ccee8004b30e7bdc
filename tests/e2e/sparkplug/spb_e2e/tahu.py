"""Eclipse Tahu's reference decoder (npm's sparkplug-payload, run by tahu/decode.js under
node) beside protoc's (codec.py): every message a test captured is decoded by both, and any
difference in a metric's name, alias, datatype, value or properties, or in a payload's seq or
timestamp, is a failure. Tahu's decoder reads each value from the field its datatype says
(Int8..Int32, UInt8 and UInt16 from int_value; UInt32, Int64, UInt64 and DateTime from
long_value), as Ignition does; protoc's reads whichever field is set. A value in the wrong
field shows as null on Tahu's side, so the two differ.

The decoder is installed by the ctest fixture "e2e: sparkplug/tahu decoder install" into the
folder TILTGATE_TAHU_DIR names (build/tests/tahu); without it the check fails, unless the fixture
found the npm registry unreachable from this machine (its file "unreachable" says why): then the
comparison is left out, and the test says so in its output."""
import base64
import json
import os
import subprocess

# Sparkplug 3.0.0, 6.4.16: the names Tahu's decodeType() gives the datatypes.
TAHU_TYPES = {"Int8": 1, "Int16": 2, "Int32": 3, "Int64": 4, "UInt8": 5, "UInt16": 6,
              "UInt32": 7, "UInt64": 8, "Float": 9, "Double": 10, "Boolean": 11, "String": 12,
              "DateTime": 13, "Text": 14, "UUID": 15}
SIGNED_32 = (1, 2, 3)
INT64 = 4
SCRIPT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tahu", "decode.js")


def install_dir(tiltgate):
    return os.environ.get("TILTGATE_TAHU_DIR") or os.path.join(
        os.path.dirname(tiltgate), "tests", "tahu")


def decode_all(tiltgate, payloads):
    """Tahu's decodePayload() of each payload (bytes), as plain JSON values."""
    modules = os.path.join(install_dir(tiltgate), "node_modules")
    if not os.path.isdir(os.path.join(modules, "sparkplug-payload")):
        raise RuntimeError("Tahu's sparkplug-payload is not installed in %s (ctest runs the "
                           "fixture \"e2e: sparkplug/tahu decoder install\")" % modules)
    lines = "".join(base64.b64encode(p).decode() + "\n" for p in payloads)
    done = subprocess.run(["node", SCRIPT], input=lines, capture_output=True, text=True,
                          env=dict(os.environ, NODE_PATH=modules), timeout=60)
    if done.returncode != 0:
        raise RuntimeError("decode.js failed: " + done.stderr[-2000:])
    decoded = [json.loads(line) for line in done.stdout.splitlines()]
    if len(decoded) != len(payloads):
        raise RuntimeError("decode.js gave %d answers for %d payloads" % (len(decoded),
                                                                          len(payloads)))
    return decoded


def number(value):
    """A Tahu number: {"long": "<decimal>"} (a protobufjs Long) or a plain JSON number."""
    if isinstance(value, dict) and "long" in value:
        return int(value["long"])
    return value


def protoc_value(datatype, value):
    """What a host makes of protoc's raw field: Int8..Int32 are two's complement in a uint32,
    Int64 in a uint64."""
    if datatype in SIGNED_32 and isinstance(value, int) and value >= 2 ** 31:
        return value - 2 ** 32
    if datatype == INT64 and isinstance(value, int) and value >= 2 ** 63:
        return value - 2 ** 64
    return value


def differences(protoc, tahu):
    """How Tahu's decoding of one payload differs from protoc's (codec.Codec.decode)."""
    if "error" in tahu:
        return ["Tahu cannot decode it: " + tahu["error"]]
    found = []
    for key in ("seq", "timestamp"):
        if protoc[key] != number(tahu.get(key)):
            found.append("%s: protoc %r, Tahu %r" % (key, protoc[key], tahu.get(key)))
    ours, theirs = protoc["metrics"], tahu.get("metrics") or []
    if len(ours) != len(theirs):
        return found + ["%d metrics by protoc, %d by Tahu" % (len(ours), len(theirs))]
    for i, (m, t) in enumerate(zip(ours, theirs)):
        where = "metric %d (%s)" % (i, m["name"] or m["alias"])
        datatype = TAHU_TYPES.get(t.get("type"))
        seen = {
            "name": (m["name"], t.get("name")),
            "alias": (m["alias"], number(t.get("alias"))),
            "timestamp": (m["timestamp"], number(t.get("timestamp"))),
            "datatype": (m["datatype"], datatype),
            "historical": (m["historical"], bool(t.get("isHistorical"))),
            "value": (None if m["null"] else protoc_value(m["datatype"], m["value"]),
                      number(t.get("value"))),
        }
        for what, (a, b) in seen.items():
            if a != b:
                found.append("%s %s: protoc %r, Tahu %r" % (where, what, a, b))
        properties = t.get("properties") or {}
        if set(m["properties"]) != set(properties):
            found.append("%s properties: protoc %r, Tahu %r" % (where, m["properties"],
                                                                properties))
            continue
        for key, pvalue in m["properties"].items():
            ptype = m["property_types"][key]
            theirs_p = properties[key]
            pair = ((ptype, protoc_value(ptype, pvalue)),
                    (TAHU_TYPES.get(theirs_p.get("type")), number(theirs_p.get("value"))))
            if pair[0] != pair[1]:
                found.append("%s property %s: protoc %r, Tahu %r" % (where, key, *pair))
    return found


def check_decoders(t, observer, tiltgate, codec):
    """The check every Sparkplug e2e test ends with: each message it captured (but STATE)
    decodes the same with Tahu's decoder as with protoc's."""
    messages = [m for m in observer.messages() if m.type != "STATE" and m.payload]
    unreachable = os.path.join(install_dir(tiltgate), "unreachable")
    if os.path.isfile(unreachable) and not os.path.isdir(
            os.path.join(install_dir(tiltgate), "node_modules", "sparkplug-payload")):
        with open(unreachable) as why:
            print("NOTE: Eclipse Tahu's decoder was not compared here: %s" % why.read().strip(),
                  flush=True)
        return True
    decoded = decode_all(tiltgate, [m.raw for m in messages])
    found = []
    for m, tahu in zip(messages, decoded):
        found += ["%d %s: %s" % (m.index, m.topic, d)
                  for d in differences(codec.decode(m.raw), tahu)]
    return t.check("Eclipse Tahu's decoder (sparkplug-payload 1.0.3) reads all %d captured "
                   "payloads as protoc's does: names, aliases, datatypes, values, properties"
                   % len(messages), messages and not found, found[:5])
