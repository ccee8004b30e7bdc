#!/usr/bin/env python3
"""A primary host going offline and online, and commands off, end to end (issue 28, "Tests"):
with `primary_host_id`, the gateway subscribes to spBv1.0/STATE/<id> and publishes its births
only while that host's retained STATE says {"online": true, "timestamp": ...}; an offline STATE
(newer than the last) makes it publish NDEATH and disconnect, an older or malformed one is not
acted on; what the host missed meanwhile is replayed as historical DDATA. With
`commands = false` a DCMD is ignored and counted. Check names carry the Sparkplug 3.0 normative
statements' ids.

Usage: /usr/bin/python3 host_state_test.py path/to/tiltgate
"""
import json
import os
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from spb_e2e import codec as spb_codec  # noqa: E402
from spb_e2e.broker import Broker  # noqa: E402
from spb_e2e.checks import Checks, arguments  # noqa: E402
from spb_e2e.observer import Observer  # noqa: E402
from spb_e2e.plant import Gateway, Simulator  # noqa: E402
from spb_e2e.processes import wait_until  # noqa: E402
from spb_e2e.tahu import check_decoders  # noqa: E402
from spb_e2e.sparkplug import device_views, seq_violations, topic  # noqa: E402

GROUP, NODE, CLIENT, HOST = "plant2", "gw2", "tg-e2e-host", "scada"
STATE = "spBv1.0/STATE/" + HOST
WAIT = 20
COMMANDS = "tiltgate_sparkplug_commands_total"
QUIET = 3  # seconds in which something must not happen (the gateway's tick is 0.1 s or so)


def now_ms():
    return int(time.time() * 1000)


def host_says(observer, online, timestamp):
    observer.publish(STATE, json.dumps({"online": online, "timestamp": timestamp}), qos=1,
                     retain=True)


def scenario(t):
    tiltgate, source = arguments()
    codec = spb_codec.Codec(source, t.dir)
    broker = Broker(t.dir)
    t.logs.append(("broker", broker.log_path))
    broker.start()
    observer = Observer(broker, codec)
    observer.start()
    sim = Simulator(tiltgate, t.dir)
    t.logs.append(("simulator", sim.err_path))
    sim.command("angle 223 12.5 -3.25")
    gateway = Gateway(tiltgate, t.dir, sim, {
        "host": "127.0.0.1", "port": broker.port, "group_id": GROUP, "edge_node_id": NODE,
        "client_id": CLIENT, "keepalive_s": 5, "state_dir": os.path.join(t.dir, "state"),
        "primary_host_id": HOST, "commands": False, "on_change_deg": 0.0,
        "min_interval_ms": 50, "max_interval_ms": 1000,
    }, sensor_keys={"poll_ms": 100})
    t.logs.append(("gateway", gateway.log_path))
    gateway.start()

    def subscribed_to_state():
        return any(e[0] == "subscribe" and e[1] == STATE for e in broker.events(CLIENT))
    t.check("tck-id-message-flow-edge-node-birth-publish-phid-wait-id: the gateway subscribes "
            "to spBv1.0/STATE/<primary_host_id>", wait_until(subscribed_to_state, WAIT),
            broker.events(CLIENT))
    t.check("the sensors are online meanwhile (HTTP API)",
            wait_until(lambda: gateway.sensor_api("boom").get("online"), WAIT))
    time.sleep(QUIET)
    t.check("tck-id-message-flow-edge-node-birth-publish-phid-wait: no birth before the primary "
            "host says online", not observer.messages("NBIRTH") and not
            observer.messages("DBIRTH"), observer.messages()[:3])

    online_at = now_ms()
    host_says(observer, True, online_at)
    nbirth = observer.wait_for(WAIT, "NBIRTH")
    if not t.check("tck-id-message-flow-edge-node-birth-publish-phid-wait-online: STATE online: "
                   "NBIRTH", nbirth, gateway.log()[-1500:]):
        return
    t.check("and the DBIRTHs",
            all(observer.wait_for(WAIT, "DBIRTH", d, nbirth.index) for d in ("boom", "mast")))
    commands_off(t, observer, gateway, codec)

    # An offline STATE older than the online one, and one that is not JSON: neither is acted on.
    since = observer.count()
    malformed = gateway.metric(COMMANDS, 0, result="malformed")
    host_says(observer, False, online_at - 60000)
    observer.publish(STATE, b"{not json", qos=1, retain=False)
    t.check("a STATE that is not JSON is counted as malformed",
            wait_until(lambda: gateway.metric(COMMANDS, 0, result="malformed") > malformed,
                       WAIT),
            {k: v for k, v in gateway.metrics().items() if "commands" in k})
    time.sleep(QUIET)
    t.check("tck-id-operational-behavior-edge-node-termination-host-offline-timestamp: an offline "
            "STATE older than the last online one is ignored: no NDEATH",
            not observer.messages("NDEATH", since=since) and
            observer.messages("DDATA", since=since), observer.messages("NDEATH", since=since))

    bd_seq = nbirth.metric("bdSeq")["value"]
    connects = len(broker.connects(CLIENT))
    since = observer.count()
    offline_at = now_ms()
    host_says(observer, False, offline_at)
    ndeath = observer.wait_for(WAIT, "NDEATH", since=since)
    if t.check("tck-id-message-flow-edge-node-birth-publish-phid-offline: STATE offline: NDEATH",
               ndeath):
        t.check("the NDEATH carries this connection's bdSeq", ndeath.metric("bdSeq") and
                ndeath.metric("bdSeq")["value"] == bd_seq, ndeath)
        events = broker.events(CLIENT)
        last_ndeath = max(i for i, e in enumerate(events) if e[0] == "publish" and
                          "NDEATH" in e[1])
        t.check("and disconnects after it", ("disconnected",) in events[last_ndeath:],
                events[last_ndeath:])
    t.check("tck-id-operational-behavior-edge-node-termination-host-offline-reconnect: it "
            "connects again (a new CONNECT)",
            wait_until(lambda: len(broker.connects(CLIENT)) > connects, WAIT),
            broker.connects(CLIENT))
    time.sleep(QUIET)
    t.check("no birth while the primary host is offline",
            not observer.messages("NBIRTH", since=since), observer.messages("NBIRTH", since=since))
    # libmosquitto kept the NDEATH (QoS 1, its PUBACK not in before the DISCONNECT) and sent it
    # again, DUP, after the next CONNACK: the old session's death in the new session.
    after = broker.publishes_after_last_connect(CLIENT)
    t.check("nothing of the closed session is sent in the new one: no PUBLISH since the new "
            "CONNECT (no DUP, no NDEATH)", not after, after)

    since = observer.count()
    back_at = now_ms()
    host_says(observer, True, back_at)
    nbirth = observer.wait_for(WAIT, "NBIRTH", since=since)
    if t.check("STATE online again: NBIRTH and the DBIRTHs", nbirth and all(
            observer.wait_for(WAIT, "DBIRTH", d, nbirth.index) for d in ("boom", "mast"))):
        expected = (len(broker.connects(CLIENT)) - 1) % 256
        t.check("tck-id-topics-nbirth-bdseq-increment: its bdSeq counts the CONNECTs (0 first)",
                nbirth.metric("bdSeq")["value"] == expected,
                (nbirth.metric("bdSeq"), broker.connects(CLIENT)))

        def replayed():
            _, data = device_views(observer.messages(), "boom")
            return [(m, n) for m, n in data if m.index > nbirth.index and
                    any(x["historical"] for x in m.metrics())]
        kept = wait_until(replayed, WAIT)
        stamps = [n["angle_x"]["timestamp"] for _, n in (kept or []) if "angle_x" in n]
        t.check("the DDATA the host missed while offline are replayed, historical, with the "
                "readings' timestamps from the offline time",
                stamps and all(offline_at - 1000 <= s <= back_at + 1000 for s in stamps),
                (offline_at, back_at, stamps[:3], stamps[-3:]))
    broken, _ = seq_violations(observer.messages())
    t.check("tck-id-payloads-sequence-num-incrementing: the seq rule holds throughout", not broken,
            broken[:5])
    check_decoders(t, observer, tiltgate, codec)


def commands_off(t, observer, gateway, codec):
    ignored = gateway.metric(COMMANDS, 0, result="ignored")
    birth = observer.messages("DBIRTH", "boom")[-1]
    zero = birth.metric("Settings/zero_x")
    metric = {"alias": zero["alias"]} if zero else {"name": "Settings/zero_x"}
    metric.update({"datatype": spb_codec.DOUBLE, "value": 1.0})
    observer.publish(topic(GROUP, NODE, "DCMD", "boom"), codec.command(now_ms(), [metric]))
    t.check("commands = false: a DCMD is ignored and counted in "
            "tiltgate_sparkplug_commands_total{result=\"ignored\"}",
            wait_until(lambda: gateway.metric(COMMANDS, 0, result="ignored") > ignored,
                       WAIT),
            {k: v for k, v in gateway.metrics().items() if "commands" in k})
    since = observer.count()

    def later_angles():
        _, data = device_views(observer.messages(), "boom")
        values = [n["angle_x"]["value"] for m, n in data if m.index >= since and "angle_x" in n]
        return values if len(values) >= 3 else None
    values = wait_until(later_angles, WAIT)
    t.check("the ignored DCMD wrote nothing: the angle stays 12.5 and zero_x unchanged",
            values and all(abs(v - 12.5) < 1e-6 for v in values) and
            abs(gateway.sensor_api("boom")["x"] - 12.5) < 1e-6, values)


if __name__ == "__main__":
    sys.exit(Checks("spb-host").run(scenario))
