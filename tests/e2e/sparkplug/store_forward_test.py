#!/usr/bin/env python3
"""Store-and-forward end to end (issue 28, "Tests"), one plant for three outages: a broker
stopped for 10 s and restarted (births first, then every reading of the outage replayed as DDATA
with is_historical = true and the original timestamps, in time order), a gateway killed and
restarted during an outage (what the first run kept is still replayed), and a store file torn
mid-record while the gateway is down (it opens, and loses at most that record). What was kept is
read from the store's files by their documented layout (spb_e2e/store_files.py), and every
record found there must come back on the broker.

Usage: /usr/bin/python3 store_forward_test.py path/to/tiltgate
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
from spb_e2e.sparkplug import device_views, seq_violations  # noqa: E402

GROUP, NODE, CLIENT = "plant3", "gw3", "tg-e2e-store"
WAIT = 20
DEVICES = ("boom", "mast")
# The most two readings of a sensor polled every 100 ms may lie apart in the stored data while
# the plant runs normally: a bound on the data, generous for a loaded machine, not a timing.
MAX_READING_GAP_MS = 3000


def now_ms():
    return int(time.time() * 1000)


def reading_time(message):
    stamps = [m["timestamp"] for m in message.metrics() if m["timestamp"] is not None]
    return stamps[0] if stamps else None


def historical(observer, device, since=0):
    """The replayed DDATA of a device from index `since`: (message, {name: metric})."""
    _, data = device_views(observer.messages(), device)
    return [(m, n) for m, n in data if m.index >= since and m.metrics() and
            all(x["historical"] for x in m.metrics())]


def live_readings(observer, device):
    _, data = device_views(observer.messages(), device)
    return [reading_time(m) for m, n in data if "angle_x" in n and
            not any(x["historical"] for x in m.metrics())]


class Plant:
    def __init__(self, t, tiltgate, source):
        self.t = t
        self.codec = spb_codec.Codec(source, t.dir)
        self.broker = Broker(t.dir, keep_sessions=True)
        t.logs.append(("broker", self.broker.log_path))
        self.broker.start()
        self.observer = Observer(self.broker, self.codec)
        self.observer.start()
        self.sim = Simulator(tiltgate, t.dir)
        t.logs.append(("simulator", self.sim.err_path))
        self.sim.command("angle 223 12.5 -3.25")
        self.sim.command("angle 101 -45")
        self.state_dir = os.path.join(t.dir, "state")
        self.gateway = Gateway(tiltgate, t.dir, self.sim, {
            "host": "127.0.0.1", "port": self.broker.port, "group_id": GROUP,
            "edge_node_id": NODE, "client_id": CLIENT, "keepalive_s": 5,
            "state_dir": self.state_dir, "on_change_deg": 0.0, "min_interval_ms": 50,
            "max_interval_ms": 1000,
        }, sensor_keys={"poll_ms": 100})
        t.logs.append(("gateway", self.gateway.log_path))
        self.gateway.start()

    def disconnected(self):
        return wait_until(lambda: self.gateway.metric("tiltgate_sparkplug_connected") == 0, WAIT)

    def kept_ddata(self):
        """The DDATA records not yet replayed, from the store's files: (device, reading time)."""
        return [(f.topic.rsplit("/", 1)[1], f.time_ms) for f in
                store_files.pending(self.state_dir) if "/DDATA/" in f.topic]

    def replayed_keys(self, since):
        return {(d, reading_time(m)) for d in DEVICES
                for m, _ in historical(self.observer, d, since)}

    def wait_replayed(self, kept, since):
        """All of `kept` replayed; the store empty again."""
        done = wait_until(lambda: set(kept) <= self.replayed_keys(since), 30)
        empty = wait_until(lambda: self.gateway.metric("tiltgate_store_records") == 0, WAIT)
        return done and empty


def scenario(t):
    tiltgate, source = arguments()
    plant = Plant(t, tiltgate, source)
    observer, gateway = plant.observer, plant.gateway
    if not t.check("births and live data before the outage",
                   observer.wait_for(WAIT, "NBIRTH") and
                   all(observer.wait_for(WAIT, "DDATA", d) for d in DEVICES),
                   gateway.log()[-1500:]):
        return
    broker_outage(t, plant)
    restart_during_outage(t, plant)
    torn_record(t, plant)
    broken, _ = seq_violations(observer.messages())
    t.check("tck-id-payloads-sequence-num-incrementing: the seq rule holds across every outage "
            "and replay", not broken, broken[:5])
    check_decoders(t, observer, tiltgate, plant.codec)
    t.check("nothing was dropped: tiltgate_store_dropped_total 0",
            gateway.metric("tiltgate_store_dropped_total") == 0,
            {k: v for k, v in gateway.metrics().items() if "store" in k})


def broker_outage(t, plant):
    observer, gateway, broker = plant.observer, plant.gateway, plant.broker
    bd_seq = observer.messages("NBIRTH")[-1].metric("bdSeq")["value"]
    connects = len(broker.connects(CLIENT))
    stopped_at = now_ms()
    broker.stop()
    t.check("the gateway sees the broker go: tiltgate_sparkplug_connected 0", plant.disconnected())
    t.check("while the broker is away the store fills: tiltgate_store_records > 0",
            wait_until(lambda: gateway.metric("tiltgate_store_records", 0) > 0, WAIT),
            {k: v for k, v in gateway.metrics().items() if "store" in k})
    time.sleep(max(0.0, 10 - (now_ms() - stopped_at) / 1000))
    since = observer.count()
    kept = plant.kept_ddata()
    t.check("the store's files hold the outage's DDATA for every sensor",
            {d for d, _ in kept} == set(DEVICES), len(kept))
    restarted_at = now_ms()
    broker.start()
    replayed = plant.wait_replayed(kept, since)
    t.check("every DDATA kept in the store during a 10 s outage is replayed after the broker "
            "restarts", replayed, (len(kept), len(plant.replayed_keys(since))))
    # A broker that stops sends the wills of its clients first (the host sees the node die):
    # what the gateway published after the restart starts after that NDEATH.
    after = [m for m in observer.messages(since=since) if m.type != "NDEATH"]
    first = [m.type for m in after[:3]]
    t.check("births first: NBIRTH and the DBIRTHs before the replay",
            first and first[0] == "NBIRTH" and
            all(any(m.type == "DBIRTH" and m.device == d for m in after[:3]) for d in DEVICES),
            [repr(m)[:80] for m in after[:4]])
    nbirth = observer.wait_for(1, "NBIRTH", since=since)
    # The gateway tried several times while the broker was away (1, 2, 4 and 8 s apart): each
    # TCP connect was refused, so no CONNECT went out and no bdSeq was used.
    sent = len(broker.connects(CLIENT)) - connects
    t.check("tck-id-topics-nbirth-bdseq-increment: across the outage bdSeq goes up by one per "
            "CONNECT the broker received, not per refused attempt",
            nbirth and sent >= 1 and nbirth.metric("bdSeq")["value"] == (bd_seq + sent) % 256,
            (bd_seq, nbirth and nbirth.metric("bdSeq"), sent))
    # Until the gateway is back on the broker (its reconnect waits a while) it keeps storing.
    connected_at = nbirth.payload["timestamp"] if nbirth else restarted_at
    for device in DEVICES:
        replay = historical(observer, device, since)
        birth = observer.wait_for(1, "DBIRTH", device, since)
        t.check("%s: the replay comes after its DBIRTH" % device,
                replay and birth and replay[0][0].index > birth.index)
        stamps = [reading_time(m) for m, _ in replay]
        t.check("%s: replayed DDATA: is_historical on every metric, by alias" % device,
                replay and all(x["historical"] and x["alias"] is not None and x["name"] is None
                               for m, _ in replay for x in m.metrics()),
                [m.metrics() for m, _ in replay[:1]])
        t.check("%s: the replay is in time order" % device,
                stamps and stamps == sorted(stamps) and len(set(stamps)) == len(stamps),
                stamps[:10])
        t.check("%s: the replay keeps the original timestamps: readings of the outage, "
                "published after it" % device,
                stamps and all(stopped_at - 1000 <= s <= connected_at for s in stamps) and
                all(m.payload["timestamp"] >= connected_at for m, _ in replay),
                (stopped_at, connected_at, stamps[:2], stamps[-2:]))
        t.check("%s: the replayed angles are the simulator's" % device,
                replay and all(abs(n["angle_x"]["value"] - {"boom": 12.5, "mast": -45.0}[device])
                               < 1e-6 for _, n in replay if "angle_x" in n),
                [n.get("angle_x") for _, n in replay[:2]])
        merged = sorted(set(live_readings(observer, device)) | set(stamps))
        inside = [s for s in merged if stopped_at - MAX_READING_GAP_MS <= s <=
                  restarted_at + MAX_READING_GAP_MS]
        gaps = [b - a for a, b in zip(inside, inside[1:])]
        t.check("%s: no reading of the outage is missing: live and replayed readings leave no "
                "gap over %d ms" % (device, MAX_READING_GAP_MS),
                inside and inside[0] <= stopped_at and inside[-1] >= restarted_at and
                max(gaps) <= MAX_READING_GAP_MS, (stopped_at, restarted_at, max(gaps or [0])))
    t.check("/metrics: tiltgate_store_replayed_total counts the replay, tiltgate_store_bytes "
            "is there", gateway.metric("tiltgate_store_replayed_total", 0) >= len(kept) and
            gateway.metric("tiltgate_store_bytes") is not None,
            {k: v for k, v in gateway.metrics().items() if "store" in k})
    t.check("live data flows again after the replay (not historical)",
            observer.wait_for(WAIT, "DDATA", "boom", observer.count(),
                              lambda m: not any(x["historical"] for x in m.metrics())))


def restart_during_outage(t, plant):
    observer, gateway, broker = plant.observer, plant.gateway, plant.broker
    broker.stop()
    plant.disconnected()
    wait_until(lambda: gateway.metric("tiltgate_store_records", 0) > 5, WAIT)
    kept_by_first = plant.kept_ddata()
    t.check("the first run keeps the outage's DDATA in the store's files",
            {d for d, _ in kept_by_first} == set(DEVICES), len(kept_by_first))
    gateway.kill()
    gateway.start()
    t.check("restarted during the outage, the gateway keeps storing",
            wait_until(lambda: len(plant.kept_ddata()) > len(kept_by_first) + 5, WAIT),
            len(plant.kept_ddata()))
    kept = plant.kept_ddata()
    since = observer.count()
    broker.start()
    t.check("a gateway killed (kill -9) and restarted during the outage still replays what its "
            "first run kept", plant.wait_replayed(kept_by_first, since),
            (len(kept_by_first), len(plant.replayed_keys(since))))
    t.check("and what its second run kept", set(kept) <= plant.replayed_keys(since),
            len(set(kept) - plant.replayed_keys(since)))


def torn_record(t, plant):
    observer, gateway, broker = plant.observer, plant.gateway, plant.broker
    broker.stop()
    plant.disconnected()
    wait_until(lambda: gateway.metric("tiltgate_store_records", 0) > 5, WAIT)
    gateway.kill()
    pending = [f for f in store_files.pending(plant.state_dir) if "/DDATA/" in f.topic]
    if not t.check("the killed gateway left DDATA records in the store", len(pending) > 2,
                   len(pending)):
        return
    last = pending[-1]
    with open(last.segment, "r+b") as f:
        f.truncate(last.offset + last.size // 2)  # a write torn mid-record
    expected = [(f.topic.rsplit("/", 1)[1], f.time_ms) for f in pending[:-1]]
    gateway.start()  # raises, failing the test, if the gateway does not start
    t.check("a store file cut mid-record: the gateway starts", gateway.running())
    t.check("the repair is logged, naming the segment",
            os.path.basename(last.segment) in gateway.log(), gateway.log()[-1500:])
    since = observer.count()
    broker.start()
    t.check("the torn store loses at most the cut record: every record before it is replayed",
            plant.wait_replayed(expected, since),
            (len(expected), len(set(expected) & plant.replayed_keys(since))))


if __name__ == "__main__":
    sys.exit(Checks("spb-store").run(scenario))
