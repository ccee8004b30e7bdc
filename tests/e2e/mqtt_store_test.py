#!/usr/bin/env python3
"""The JSON [mqtt] feed's backlog in the on-disk store end to end (issue 28, "The JSON [mqtt]
feed keeps its backlog in the same store"): a broker stopped while the gateway is killed and
restarted (every state kept in <state_dir>/mqtt/ by either run comes back on the broker once it
is back, marked "historical", in time order, and no reading of the outage is missing), and a
small buffer_mb (the oldest dropped and counted, the newest replayed). What was kept is read from
the store's files by their documented layout (spb_e2e/store_files.py), not by the gateway's code.
The broker keeps the observer's session, so nothing the gateway sends while the observer
reconnects is missed. Uses the Python e2e library of tests/e2e/sparkplug/spb_e2e/.

Usage: /usr/bin/python3 mqtt_store_test.py path/to/tiltgate
"""
import json
import os
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "sparkplug"))
from spb_e2e import store_files  # noqa: E402
from spb_e2e.broker import Broker  # noqa: E402
from spb_e2e.checks import Checks, arguments  # noqa: E402
from spb_e2e.observer import Observer  # noqa: E402
from spb_e2e.plant import Gateway, Simulator  # noqa: E402
from spb_e2e.processes import wait_until  # noqa: E402

PREFIX = "e2e/store"
SENSORS = ("boom", "mast")
WAIT = 20
# The most two readings of a sensor polled every 100 ms may lie apart in what the subscriber
# gets, live and replayed together: a bound on the data, generous for a loaded machine.
MAX_READING_GAP_MS = 3000


def now_ms():
    return int(time.time() * 1000)


class JsonObserver(Observer):
    """A subscriber to <prefix>/# with a persistent MQTT 5 session (spb_e2e/observer.py's): every
    state it got, in the order the broker delivered them, as (index, sensor, state dict, raw)."""

    def __init__(self, broker):
        super().__init__(broker, None, client_id="json-observer", topic=PREFIX + "/#")
        self._states = []

    def _on_message(self, client, userdata, msg):
        parts = msg.topic.split("/")
        if len(parts) != 4 or parts[3] != "state":
            return
        with self._lock:
            self._states.append((len(self._states), parts[2], json.loads(msg.payload), msg.payload))

    def count(self):
        with self._lock:
            return len(self._states)

    def states(self, sensor=None, since=0, historical=None):
        with self._lock:
            found = list(self._states[since:])
        return [s for s in found if (sensor is None or s[1] == sensor) and
                (historical is None or bool(s[2].get("historical")) == historical)]


def kept(state_dir):
    """The states in the store's files not yet replayed: (sensor, payload bytes). The store
    keeps the monitoring's events (<prefix>/events) too: they are not states."""
    return [(f.topic.split("/")[2], bytes(f.payload)) for f in
            store_files.pending(os.path.join(state_dir, "mqtt")) if f.topic.endswith("/state")]


def mqtt_table(broker, state_dir, client_id, **more):
    keys = {"host": "127.0.0.1", "port": broker.port, "client_id": client_id,
            "topic_prefix": PREFIX, "interval_ms": 200, "on_change_deg": 0.0,
            "keepalive_s": 5, "state_dir": state_dir}
    keys.update(more)
    return keys


def store_metrics(gateway):
    return {k: v for k, v in gateway.metrics().items() if "store" in k or "mqtt" in k}


def restart_during_outage(t, tiltgate, broker, observer, sim):
    state_dir = os.path.join(t.dir, "state")
    gateway = Gateway(tiltgate, t.dir, sim, None, sensor_keys={"poll_ms": 100},
                      mqtt=mqtt_table(broker, state_dir, "tg-e2e-json-store"))
    t.logs.append(("gateway", gateway.log_path))
    gateway.start()
    t.check("live states of every sensor before the outage",
            wait_until(lambda: all(observer.states(s) for s in SENSORS), WAIT),
            gateway.log()[-1500:])

    stopped_at = now_ms()
    broker.stop()
    t.check("the gateway sees the broker go: tiltgate_mqtt_connected 0",
            wait_until(lambda: gateway.metric("tiltgate_mqtt_connected") == 0, WAIT))
    t.check("while the broker is away the states go to the store: "
            "tiltgate_store_records{feed=\"mqtt\"} > 0",
            wait_until(lambda: gateway.metric("tiltgate_store_records", 0, feed="mqtt") > 5, WAIT),
            store_metrics(gateway))
    first_run = kept(state_dir)
    t.check("the store's files under state_dir/mqtt hold the outage's states of every sensor",
            {s for s, _ in first_run} == set(SENSORS), len(first_run))
    gateway.kill()
    gateway.start()
    t.check("restarted during the outage, the gateway keeps storing after what the first run kept",
            wait_until(lambda: len(kept(state_dir)) > len(first_run) + 10, WAIT),
            len(kept(state_dir)))
    time.sleep(max(0.0, 10 - (now_ms() - stopped_at) / 1000))
    waiting = kept(state_dir)
    t.check("what the killed run kept is still in the store after the restart",
            set(first_run) <= set(waiting), (len(first_run), len(waiting)))

    since = observer.count()
    restarted_at = now_ms()
    broker.start()
    replayed = lambda: {(s, raw) for _, s, _, raw in observer.states(since=since, historical=True)}
    t.check("every state kept in the store, by either run, is published once the broker is back",
            wait_until(lambda: set(waiting) <= replayed(), 40),
            (len(waiting), len(replayed())))
    t.check("the store is empty again: tiltgate_store_records{feed=\"mqtt\"} 0",
            wait_until(lambda: gateway.metric("tiltgate_store_records", feed="mqtt") == 0, WAIT),
            store_metrics(gateway))
    for sensor in SENSORS:
        history = observer.states(sensor, since, historical=True)
        stamps = [state["ts"] for _, _, state, _ in history]
        t.check("%s: the replayed states are in time order, with the readings' own times" % sensor,
                stamps and stamps == sorted(stamps) and
                all(stopped_at - 1000 <= ts <= now_ms() for ts in stamps), stamps[:10])
        live = [state["ts"] for _, _, state, _ in observer.states(sensor, historical=False)]
        merged = sorted(set(live) | set(stamps))
        inside = [s for s in merged
                  if stopped_at - MAX_READING_GAP_MS <= s <= restarted_at + MAX_READING_GAP_MS]
        gaps = [b - a for a, b in zip(inside, inside[1:])]
        t.check("%s: no reading of the outage is missing: live and replayed states leave no gap "
                "over %d ms (the killed gateway's restart included)" % (sensor, MAX_READING_GAP_MS),
                inside and inside[0] <= stopped_at and inside[-1] >= restarted_at and
                max(gaps) <= MAX_READING_GAP_MS, (stopped_at, restarted_at, max(gaps or [0])))
    after = observer.count()
    t.check("live states flow again after the replay (not historical)",
            wait_until(lambda: observer.states("boom", after, historical=False), WAIT))
    t.check("/metrics: tiltgate_store_replayed_total{feed=\"mqtt\"} counts the replay, nothing "
            "dropped", gateway.metric("tiltgate_store_replayed_total", 0, feed="mqtt") > 0 and
            gateway.metric("tiltgate_store_dropped_total", feed="mqtt") == 0 and
            gateway.metric("tiltgate_store_bytes", feed="mqtt") is not None,
            store_metrics(gateway))
    gateway.stop()


def full_store(t, tiltgate, broker, observer, sim):
    state_dir = os.path.join(t.dir, "small-state")
    gateway = Gateway(tiltgate, t.dir, sim, None, sensor_keys={"poll_ms": 100},
                      name="small-gateway",
                      mqtt=mqtt_table(broker, state_dir, "tg-e2e-json-small", buffer_mb=0.02))
    t.logs.append(("small gateway", gateway.log_path))
    gateway.start()
    wait_until(lambda: gateway.metric("tiltgate_mqtt_connected") == 1, WAIT)
    stopped_at = now_ms()
    broker.stop()
    t.check("a store of buffer_mb = 0.02 fills while the broker is away and drops the oldest: "
            "tiltgate_store_dropped_total{feed=\"mqtt\"} > 0",
            wait_until(lambda: gateway.metric("tiltgate_store_dropped_total", 0, feed="mqtt") > 20,
                       40), store_metrics(gateway))
    t.check("the store stays within buffer_mb on disk",
            gateway.metric("tiltgate_store_bytes", feed="mqtt") <= 0.02 * 1024 * 1024,
            store_metrics(gateway))
    waiting = kept(state_dir)
    since = observer.count()
    broker.start()
    replayed = lambda: {(s, raw) for _, s, _, raw in observer.states(since=since, historical=True)}
    t.check("what the full store kept is published once the broker is back",
            wait_until(lambda: set(waiting) <= replayed(), 40), (len(waiting), len(replayed())))
    first = min((state["ts"] for _, _, state, _ in observer.states(since=since, historical=True)),
                default=None)
    t.check("the oldest were dropped: the replay starts well after the outage began",
            first is not None and first > stopped_at + 500, (stopped_at, first))
    t.check("the drops are logged",
            "backlog full while the broker is away" in gateway.log(), gateway.log()[-800:])
    gateway.stop()


def scenario(t):
    tiltgate, _ = arguments()
    broker = Broker(t.dir, keep_sessions=True)
    t.logs.append(("broker", broker.log_path))
    broker.start()
    observer = JsonObserver(broker)
    observer.start()
    sim = Simulator(tiltgate, t.dir)
    t.logs.append(("simulator", sim.err_path))
    restart_during_outage(t, tiltgate, broker, observer, sim)
    full_store(t, tiltgate, broker, observer, sim)


if __name__ == "__main__":
    sys.exit(Checks("mqtt-store").run(scenario))
