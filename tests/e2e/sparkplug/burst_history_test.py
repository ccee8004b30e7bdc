#!/usr/bin/env python3
"""A burst published as historical data (issue 57, item 4; docs/monitoring.md, "Bursts"), against
a mosquitto of the test's own: a mast under `tiltgate sim rieker` steps past its alarm, and the
burst that starts goes out on the JSON feed as <prefix>/mast/burst messages (the samples before
the trigger, the trigger, then the burst's, each with its reading's time, "historical": true)
beside the burst's events on <prefix>/events, and on the Sparkplug edge node as DDATA whose
metrics are marked historical, by alias, each value with its sample's timestamp, decoded by
protoc's Python output: many values of angle_x in one payload, in time order, the trigger's
above the alarm.

Usage: /usr/bin/python3 burst_history_test.py path/to/tiltgate
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

GROUP, NODE, PREFIX = "plant1", "gw1", "burstfeed"
WAIT = 20  # seconds: generous, never a measurement
BURST_S = 2
ALARM = 2.0


def json_messages(observer, suffix):
    out = []
    for m in observer.messages():
        if m.topic.endswith(suffix):
            try:
                out.append(json.loads(m.raw))
            except ValueError:
                out.append({"undecodable": m.raw})
    return out


def scenario(t):
    tiltgate, source = arguments()
    codec = spb_codec.Codec(source, t.dir)
    broker = Broker(t.dir)
    t.logs.append(("broker", broker.log_path))
    broker.start()
    sparkplug = Observer(broker, codec, client_id="spb-observer")
    sparkplug.start()
    feed = Observer(broker, codec, client_id="json-observer", topic=PREFIX + "/#")
    feed.start()
    sim = Simulator(tiltgate, t.dir)
    t.logs.append(("simulator", sim.err_path))
    t.check("the simulator takes the angles, both below the alarm",
            sim.command("angle 101 1.0") == "ok" and sim.command("angle 223 0.5 0.0") == "ok")
    state_dir = os.path.join(t.dir, "state")
    gateway = Gateway(tiltgate, t.dir, sim, {
        "host": "127.0.0.1", "port": broker.port, "group_id": GROUP, "edge_node_id": NODE,
        "client_id": "tg-e2e-burst-spb", "keepalive_s": 5, "state_dir": state_dir,
    }, sensor_keys={"poll_ms": 100, "burst_s": BURST_S, "pre_trigger_s": 1,
                    "alarms": {"x_high": ALARM}},
        mqtt={"host": "127.0.0.1", "port": broker.port, "client_id": "tg-e2e-burst-json",
              "topic_prefix": PREFIX, "keepalive_s": 5, "state_dir": state_dir})
    t.logs.append(("gateway", gateway.log_path))
    gateway.start()
    t.check("the mast is born on the edge node", sparkplug.wait_for(WAIT, "DBIRTH", "mast"),
            gateway.log()[-2000:])
    time.sleep(1.5)  # a second of samples before the trigger
    stepped_at = int(time.time() * 1000)
    t.check("the simulator takes the step", sim.command("angle 101 3.0") == "ok")

    def burst_done():
        phases = [b.get("phase") for b in json_messages(feed, "/mast/burst")]
        events = [(e.get("kind"), e.get("state")) for e in json_messages(feed, "/events")]
        return ("burst", "end") in events and "burst" in phases and phases
    phases = wait_until(burst_done, WAIT)
    t.check("the JSON feed publishes the burst on burstfeed/mast/burst: pre, trigger, then burst",
            phases and phases[0] == "pre" and phases[1] == "trigger" and
            set(phases[2:]) == {"burst"}, phases)
    batches = json_messages(feed, "/mast/burst")
    samples = [s for b in batches for s in b.get("samples", [])]
    stamps = [s["ts"] for s in samples]
    t.check("each batch is marked historical, names the sensor and one burst id",
            batches and all(b.get("historical") is True and b.get("sensor") == "mast"
                            for b in batches) and len({b.get("burst") for b in batches}) == 1,
            [{k: v for k, v in b.items() if k != "samples"} for b in batches])
    t.check("its samples are in time order, a second before the trigger and the burst's after",
            stamps == sorted(stamps) and stamps and stamps[0] < stepped_at - 500 and
            len(samples) >= BURST_S * 10, (len(samples), stamps[:3], stepped_at))
    trigger = [s for b in batches if b.get("phase") == "trigger" for s in b["samples"]]
    t.check("the trigger's sample is past the alarm", len(trigger) == 1 and
            trigger[0]["x"] > ALARM and trigger[0]["temperature"] is None, trigger)
    events = [(e.get("kind"), e.get("state")) for e in json_messages(feed, "/events")]
    t.check("the burst's start and end are on burstfeed/events too",
            ("burst", "start") in events and ("burst", "end") in events, events)

    def historical_ddata():
        found = []
        for m in sparkplug.messages("DDATA", "mast"):
            historical = [x for x in m.metrics() if x["historical"]]
            if historical:
                found.append((m, historical))
        count = sum(len(h) for _, h in found)
        return found if count >= BURST_S * 10 * 3 else None  # angle_x, tilt, relative_x each
    found = wait_until(historical_ddata, WAIT)
    t.check("the edge node publishes the burst as DDATA with historical metrics",
            found, [m for m in sparkplug.messages("DDATA", "mast")][-3:])
    if not found:
        return
    birth = sparkplug.messages("DBIRTH", "mast")[-1]
    aliases = {x["name"]: x["alias"] for x in birth.metrics()}
    metrics = [x for _, h in found for x in h]
    angle_x = [x for x in metrics if x["alias"] == aliases.get("angle_x")]
    t.check("by the birth's aliases, each value with its sample's timestamp, in time order",
            all(x["alias"] in aliases.values() and x["timestamp"] for x in metrics) and
            [x["timestamp"] for x in angle_x] == sorted(x["timestamp"] for x in angle_x) and
            len(angle_x) >= BURST_S * 10, (len(angle_x), angle_x[:3]))
    t.check("several values of angle_x in one payload", any(
        sum(1 for x in h if x["alias"] == aliases.get("angle_x")) > 1 for _, h in found),
        [len(h) for _, h in found])
    t.check("the step shows in them: before the trigger below the alarm, after it above",
            any(x["value"] < ALARM and x["timestamp"] < stepped_at for x in angle_x) and
            any(x["value"] > ALARM and x["timestamp"] >= stepped_at for x in angle_x),
            [(x["timestamp"] - stepped_at, round(x["value"], 2)) for x in angle_x][:40])
    seqs = [m.seq for m in sparkplug.messages()]
    t.check("the seq of the node's messages stays in order with them",
            all((b - a) % 256 == 1 for a, b in zip(seqs, seqs[1:]) if a is not None and
                b is not None), seqs[-30:])
    feed.close()
    sparkplug.close()
    t.check("the gateway stops cleanly", gateway.stop() == 0)


if __name__ == "__main__":
    sys.exit(Checks("burst-history").run(scenario))
