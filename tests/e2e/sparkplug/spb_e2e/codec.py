"""Sparkplug B payloads with Debian's python3-protobuf: sparkplug/sparkplug_b.proto compiled by
protoc into the test's scratch folder, so the decoder shares no code with the gateway's
protobuf-c encoder."""
import importlib
import os
import subprocess
import sys

# Sparkplug 3.0.0, 6.4.16 "Datatypes".
INT64 = 4
UINT16 = 6
UINT32 = 7
DOUBLE = 10
BOOLEAN = 11
STRING = 12

_VALUE_FIELDS = ("int_value", "long_value", "float_value", "double_value", "boolean_value",
                 "string_value")


class Codec:
    def __init__(self, source_dir, scratch_dir):
        out = os.path.join(scratch_dir, "pb2")
        os.makedirs(out, exist_ok=True)
        proto_dir = os.path.join(source_dir, "sparkplug")
        subprocess.run(["/usr/bin/protoc", "--proto_path=" + proto_dir, "--python_out=" + out,
                        os.path.join(proto_dir, "sparkplug_b.proto")], check=True)
        sys.path.insert(0, out)
        self.pb = importlib.import_module("sparkplug_b_pb2")

    def decode(self, payload):
        """The payload as a plain dict: timestamp, seq (None when absent) and metrics, each
        {name, alias, timestamp, datatype, historical, null, value (of whichever field is set),
        properties ({key: value}), property_types ({key: datatype})}."""
        message = self.pb.Payload()
        message.ParseFromString(payload)
        return {
            "timestamp": message.timestamp if message.HasField("timestamp") else None,
            "seq": message.seq if message.HasField("seq") else None,
            "metrics": [self._metric(m) for m in message.metrics],
        }

    def _metric(self, m):
        properties, property_types = {}, {}
        if m.HasField("properties"):
            for key, value in zip(m.properties.keys, m.properties.values):
                which = value.WhichOneof("value")
                properties[key] = getattr(value, which) if which else None
                property_types[key] = value.type
        which = m.WhichOneof("value")
        return {
            "name": m.name if m.HasField("name") else None,
            "alias": m.alias if m.HasField("alias") else None,
            "timestamp": m.timestamp if m.HasField("timestamp") else None,
            "datatype": m.datatype if m.HasField("datatype") else None,
            "historical": m.is_historical if m.HasField("is_historical") else False,
            "null": m.is_null if m.HasField("is_null") else False,
            "value": getattr(m, which) if which in _VALUE_FIELDS else None,
            "properties": properties,
            "property_types": property_types,
        }

    def command(self, timestamp_ms, metrics):
        """An NCMD/DCMD payload; metrics: dicts with name or alias, datatype and value."""
        message = self.pb.Payload()
        message.timestamp = timestamp_ms
        for spec in metrics:
            m = message.metrics.add()
            if "name" in spec:
                m.name = spec["name"]
            if "alias" in spec:
                m.alias = spec["alias"]
            m.timestamp = timestamp_ms
            m.datatype = spec["datatype"]
            if spec["datatype"] == BOOLEAN:
                m.boolean_value = spec["value"]
            elif spec["datatype"] == DOUBLE:
                m.double_value = spec["value"]
            elif spec["datatype"] in (INT64,):
                m.long_value = spec["value"]
            else:
                m.int_value = spec["value"]
        return message.SerializeToString()
