#!/usr/bin/env python3
"""A full store end to end (issue 28, "Tests"): with the smallest budget (`buffer_mb = 1`) and a
broker away long enough to fill it, the store's files never exceed the budget, the oldest
records are dropped (whole segments, docs/northbound.md "The store") and counted in
tiltgate_store_dropped_total, and once the broker is back what is left (the newest) is replayed
in time order. Twenty sensors on two simulated buses, polled every 50 ms, fill a MiB in about
30 s: the longest of the Sparkplug e2e tests, about 75 s in all.

Usage: /usr/bin/python3 store_full_test.py path/to/tiltgate
"""
import os
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from spb_e2e import codec as spb_codec  # noqa: E402
from spb_e2e import store_files  # noqa: E402
from spb_e2e.broker import Broker  # noqa: E402
from spb_e2e.checks import Checks, arguments  # noqa: E402
from spb_e2e.observer import Observer  # noqa: E402
from spb_e2e.plant import Gateway, Simulator  # noqa: E402
from spb_e2e.processes import wait_until  # noqa: E402
from spb_e2e.tahu import check_decoders  # noqa: E402
from spb_e2e.sparkplug import device_views  # noqa: E402

GROUP, NODE, CLIENT = "plant4", "gw4", "tg-e2e-full"
WAIT = 20
# Seconds for 1 MiB of DDATA (about 30 here), and for the replay, which starts once the
# gateway's reconnect back-off (up to 30 s after an outage this long) has found the broker again:
# generous, never a measurement.
FILL_WAIT = 120
BUDGET = 1024 * 1024


def bus_sensors(first):
    return {"s%02d" % n: {"model": "h6", "address": n, "unit_id": n}
            for n in range(first, first + 10)}


def kept_ddata(state_dir):
    """The DDATA records not yet replayed, from the store's files: (device, reading time)."""
    return [(f.topic.rsplit("/", 1)[1], f.time_ms) for f in store_files.pending(state_dir)
            if "/DDATA/" in f.topic]


def scenario(t):
    tiltgate, source = arguments()
    codec = spb_codec.Codec(source, t.dir)
    broker = Broker(t.dir, keep_sessions=True)
    t.logs.append(("broker", broker.log_path))
    broker.start()
    observer = Observer(broker, codec)
    observer.start()
    sims = [Simulator(tiltgate, t.dir, bus_sensors(1), "sim1"),
            Simulator(tiltgate, t.dir, bus_sensors(11), "sim2")]
    state_dir = os.path.join(t.dir, "state")
    gateway = Gateway(tiltgate, t.dir, sims, {
        "host": "127.0.0.1", "port": broker.port, "group_id": GROUP, "edge_node_id": NODE,
        "client_id": CLIENT, "keepalive_s": 5, "state_dir": state_dir, "on_change_deg": 0.0,
        "min_interval_ms": 0, "max_interval_ms": 1000, "buffer_mb": 1,
    }, sensor_keys={"poll_ms": 50})
    t.logs.append(("gateway", gateway.log_path))
    gateway.start()
    devices = [n for sim in sims for n in sim.sensors]
    if not t.check("births and data for all 20 sensors",
                   observer.wait_for(WAIT, "NBIRTH") and
                   all(observer.wait_for(WAIT, "DDATA", d) for d in devices),
                   gateway.log()[-1500:]):
        return

    broker.stop()
    t.check("the broker is gone: tiltgate_sparkplug_connected 0",
            wait_until(lambda: gateway.metric("tiltgate_sparkplug_connected") == 0, WAIT))
    wait_until(lambda: len(kept_ddata(state_dir)) >= 40, WAIT)
    oldest = kept_ddata(state_dir)[:40]
    largest = [0]

    def dropped():
        largest[0] = max(largest[0], gateway.metric("tiltgate_store_bytes", 0),
                         sum(os.path.getsize(p) for p in store_files.segments(state_dir)))
        return gateway.metric("tiltgate_store_dropped_total", 0) > 0
    if not t.check("the store fills: tiltgate_store_dropped_total > 0 with buffer_mb = 1",
                   wait_until(dropped, FILL_WAIT, interval_s=0.5),
                   {k: v for k, v in gateway.metrics().items() if "store" in k}):
        return
    time.sleep(1)
    dropped()
    t.check("the store's files never exceed buffer_mb (1 MiB)", largest[0] <= BUDGET, largest[0])
    # What the store holds now, by segment, oldest first. The store goes on filling until the
    # gateway is connected again, and may drop more whole oldest segments meanwhile, but never
    # the newest one of this snapshot: that takes filling another segment first.
    by_segment = [[(f.topic.rsplit("/", 1)[1], f.time_ms) for f in store_files.frames(path)
                   if "/DDATA/" in f.topic] for path in store_files.segments(state_dir)]
    remaining = {key for segment in by_segment for key in segment}
    t.check("the oldest records are gone from the store's files",
            not set(oldest) & remaining, len(set(oldest) & remaining))
    t.check("tiltgate_store_dropped_total counts at least the records dropped",
            gateway.metric("tiltgate_store_dropped_total", 0) >= len(oldest),
            gateway.metric("tiltgate_store_dropped_total"))

    since = observer.count()
    broker.start()

    def replayed():
        found = set()
        for device in devices:
            _, data = device_views(observer.messages(), device)
            for m, _ in data:
                if m.index >= since and m.metrics() and all(x["historical"]
                                                             for x in m.metrics()):
                    found.add((device, m.metrics()[0]["timestamp"]))
        return found
    newest = set(by_segment[-1]) if by_segment else set()
    t.check("what the store kept (the newest) is replayed once the broker is back",
            newest and wait_until(lambda: newest <= replayed(), FILL_WAIT, interval_s=0.5),
            (len(newest), len(newest & replayed())))
    t.check("the store is empty after the replay: tiltgate_store_records 0",
            wait_until(lambda: gateway.metric("tiltgate_store_records") == 0, WAIT),
            {k: v for k, v in gateway.metrics().items() if "store" in k})
    found = replayed()
    shares = [len(set(segment) & found) / max(1, len(segment)) for segment in by_segment]
    t.check("older segments are replayed whole or dropped whole, the oldest first",
            all(x in (0.0, 1.0) for x in shares) and shares == sorted(shares), shares)
    t.check("the dropped (oldest) records are not replayed", not set(oldest) & found,
            len(set(oldest) & found))
    for device in devices[:3]:
        _, data = device_views(observer.messages(), device)
        stamps = [m.metrics()[0]["timestamp"] for m, _ in data if m.index >= since and
                  m.metrics() and all(x["historical"] for x in m.metrics())]
        t.check("%s: the replay is in time order" % device, stamps and stamps == sorted(stamps),
                stamps[:5])
    check_decoders(t, observer, tiltgate, codec)


if __name__ == "__main__":
    sys.exit(Checks("spb-full").run(scenario))
