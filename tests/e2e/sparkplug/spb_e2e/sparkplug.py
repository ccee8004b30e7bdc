"""What Sparkplug 3.0 says of a recorded message flow, as plain functions over the observer's
messages (observer.Message): the seq rule, a device's metrics by name through its DBIRTH's
aliases, and the topics of a node."""


def topic(group, node, type, device=None):
    return "spBv1.0/%s/%s/%s" % (group, type, node) + ("/" + device if device else "")


def seq_violations(messages):
    """tck-id-payloads-sequence-num-incrementing: every message of the node (each a Sparkplug B
    payload) but NDEATH has a seq, 0 in each NBIRTH and one more (mod 256) than the message
    before it otherwise, in the order they arrived. Returns what breaks the rule (empty: none)
    and how many times it wrapped from 255 to 0."""
    broken = []
    wraps = 0
    previous = None
    for m in messages:
        if m.type in ("STATE", "NCMD", "DCMD"):
            continue
        if m.undecodable:
            broken.append("not a Sparkplug B payload (%s): %r" % (m.undecodable, m))
            continue
        if m.type == "NDEATH":
            if m.seq is not None:
                broken.append("NDEATH with a seq: %r" % m)
            previous = None  # the next connection starts with an NBIRTH
            continue
        if m.seq is None:
            broken.append("no seq: %r" % m)
            continue
        if m.type == "NBIRTH":
            if m.seq != 0:
                broken.append("NBIRTH seq %d: %r" % (m.seq, m))
        elif previous is None:
            broken.append("no NBIRTH before: %r" % m)
        elif m.seq != (previous + 1) % 256:
            broken.append("seq %d after %d: %r" % (m.seq, previous, m))
        elif previous == 255:
            wraps += 1
        previous = m.seq
    return broken, wraps


class DeviceView:
    """A device's metrics as a host reads them: names from the last DBIRTH, then DDATA by
    alias. `values` is each metric's latest (value, timestamp, historical)."""

    def __init__(self):
        self.by_alias = {}
        self.birth = None

    def on_birth(self, message):
        self.birth = message
        self.by_alias = {m["alias"]: m["name"] for m in message.metrics()}

    def names_in(self, message):
        """The DDATA's metrics as {name: metric}; a metric of an unknown alias under None."""
        out = {}
        for m in message.metrics():
            out[self.by_alias.get(m["alias"])] = m
        return out


def device_views(messages, device):
    """(DeviceView, [(message, {name: metric})]) of one device over the messages: each DDATA
    named by the DBIRTH before it."""
    view = DeviceView()
    data = []
    for m in messages:
        if m.device != device:
            continue
        if m.type == "DBIRTH":
            view.on_birth(m)
        elif m.type == "DDATA" and view.birth is not None:
            data.append((m, view.names_in(m)))
    return view, data


def birth_value(birth, name):
    metric = birth.metric(name)
    return metric["value"] if metric else None
