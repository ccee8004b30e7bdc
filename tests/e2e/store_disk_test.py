#!/usr/bin/env python3
"""The stores on a disk that refuses, end to end (issue 40, item 3), with build/tiltgate, a real
mosquitto and each state_dir on a small tmpfs of the test's own, filled to ENOSPC:

- [mqtt]: the broker returns while the disk is full, so the replay cannot save its cursor: it
  goes on from its place in memory (no state sent more than twice, the store drains), says so
  once, and saves its place once the disk has room again.
- [sparkplug]: bdSeq cannot be written, yet the edge node connects (NBIRTH) with the next bdSeq
  and says why; the DDATA of an outage on the full disk are kept (in memory) and replayed.
- a record corrupted in the middle of a segment while the gateway is stopped: the records lost
  with it are counted in tiltgate_store_lost_total{feed="mqtt"} and said in the log.
- [mqtt] whose state directory cannot be used at the start (here: locked by another process)
  keeps its backlog in memory and moves it to the directory once it can be used, by itself.

Runs in a mount namespace of its own (unshare -m), so no mount outlives it whatever happens;
needs root, as CI runs (exit 77, skipped, otherwise).

Usage: /usr/bin/python3 store_disk_test.py path/to/tiltgate
"""
import collections
import fcntl
import os
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "support"))
from small_disk import SmallDisk, run_in_own_mount_namespace  # noqa: E402

run_in_own_mount_namespace()
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "sparkplug"))
from mqtt_store_test import JsonObserver, kept, mqtt_table, store_metrics  # noqa: E402
from spb_e2e import codec as spb_codec  # noqa: E402
from spb_e2e import store_files  # noqa: E402
from spb_e2e.broker import Broker  # noqa: E402
from spb_e2e.checks import Checks, arguments  # noqa: E402
from spb_e2e.observer import Observer  # noqa: E402
from spb_e2e.plant import Gateway, Simulator  # noqa: E402
from spb_e2e.processes import wait_until  # noqa: E402

WAIT = 20
# The replay of a few hundred states at 500 a second, after the reconnect's back-off: generous.
REPLAY_WAIT = 60


def mqtt_replay_on_a_full_disk(t, tiltgate, broker, sim, disk):
    observer = JsonObserver(broker)
    observer.start()
    state_dir = os.path.join(disk.path, "state")
    gateway = Gateway(tiltgate, t.dir, sim, None, sensor_keys={"poll_ms": 100}, name="mqtt-gw",
                      mqtt=mqtt_table(broker, state_dir, "tg-e2e-disk-json"))
    t.logs.append(("mqtt gateway", gateway.log_path))
    gateway.start()
    wait_until(lambda: gateway.metric("tiltgate_mqtt_connected") == 1, WAIT)
    broker.stop()
    t.check("while the broker is away the states go to the store",
            wait_until(lambda: gateway.metric("tiltgate_store_records", 0, feed="mqtt") > 80,
                       WAIT), store_metrics(gateway))
    disk.fill()
    time.sleep(2)  # states now kept in memory, after those on disk
    waiting = gateway.metric("tiltgate_store_records", 0, feed="mqtt")
    since = observer.count()
    broker.start()
    t.check("with the cursor refused by the full disk, the replay still ends: "
            "tiltgate_store_records{feed=\"mqtt\"} 0",
            wait_until(lambda: gateway.metric("tiltgate_store_records", feed="mqtt") == 0,
                       REPLAY_WAIT), store_metrics(gateway))
    history = observer.states(since=since, historical=True)
    copies = collections.Counter((s, state["ts"]) for _, s, state, _ in history)
    t.check("no state is sent more than twice (at worst one batch again), none in a loop",
            copies and max(copies.values()) <= 2 and len(history) <= waiting + 100,
            (waiting, len(history), copies.most_common(3)))
    t.check("nothing was dropped: tiltgate_store_dropped_total{feed=\"mqtt\"} 0",
            gateway.metric("tiltgate_store_dropped_total", feed="mqtt") == 0,
            store_metrics(gateway))
    log = gateway.log()
    refusals = log.count("the replay goes on from its place in memory")
    t.check("the disk's refusal is said once, not at every record or batch",
            1 <= refusals <= log.count("the disk takes writes again") + 1, log[-1500:])
    disk.free()
    t.check("once the disk has room the store says it writes again",
            wait_until(lambda: "the disk takes writes again" in gateway.log(), WAIT),
            gateway.log()[-800:])
    t.check("and the replay's place is saved: the store's files hold nothing still to replay",
            wait_until(lambda: not kept(state_dir), WAIT), len(kept(state_dir)))
    gateway.stop()
    observer.close()
    return state_dir


def lost_to_a_corrupt_record(t, tiltgate, broker, sim, state_dir):
    gateway = Gateway(tiltgate, t.dir, sim, None, sensor_keys={"poll_ms": 100}, name="lost-gw",
                      mqtt=mqtt_table(broker, state_dir, "tg-e2e-disk-lost"))
    t.logs.append(("lost gateway", gateway.log_path))
    broker.stop()
    gateway.start()
    wait_until(lambda: gateway.metric("tiltgate_store_records", 0, feed="mqtt") > 40, WAIT)
    gateway.stop()
    segment = store_files.segments(state_dir)[-1]
    frames = store_files.frames(segment)
    t.check("the stopped gateway left states in a segment", len(frames) > 20, len(frames))
    victim = len(frames) // 2
    with open(segment, "r+b") as f:  # one byte of a record's payload in the middle
        f.seek(frames[victim].offset + frames[victim].size - 3)
        byte = f.read(1)
        f.seek(-1, os.SEEK_CUR)
        f.write(bytes([byte[0] ^ 0x55]))
    lost = len(frames) - victim
    gateway.start()
    t.check("the records lost with the corrupt one are counted: "
            "tiltgate_store_lost_total{feed=\"mqtt\"} %d" % lost,
            wait_until(lambda: gateway.metric("tiltgate_store_lost_total", feed="mqtt") == lost,
                       WAIT), store_metrics(gateway))
    t.check("and said in the log, with how many",
            "a corrupt record, %d records lost" % lost in gateway.log(), gateway.log()[-800:])
    gateway.stop()
    broker.start()


def state_dir_usable_later(t, tiltgate, broker, sim):
    state_dir = os.path.join(t.dir, "later-state")
    os.makedirs(os.path.join(state_dir, "mqtt"))
    holder = open(os.path.join(state_dir, "mqtt", "lock"), "w")
    fcntl.flock(holder, fcntl.LOCK_EX | fcntl.LOCK_NB)  # "another tiltgate"
    gateway = Gateway(tiltgate, t.dir, sim, None, sensor_keys={"poll_ms": 100}, name="later-gw",
                      mqtt=mqtt_table(broker, state_dir, "tg-e2e-disk-later"))
    t.logs.append(("later gateway", gateway.log_path))
    broker.stop()
    gateway.start()
    t.check("with its state directory in use, the backlog is kept in memory",
            wait_until(lambda: gateway.metric("tiltgate_store_records", 0, feed="mqtt") > 10,
                       WAIT) and not kept(state_dir), store_metrics(gateway))
    holder.close()  # the directory is free now
    t.check("once the directory can be used, what memory held moves there, no restart needed",
            # Both in one wait: the records reach the files before the line that says so
            # reaches the log, and a look between the two must not fail the test.
            wait_until(lambda: len(kept(state_dir)) > 10 and
                       "messages moved there from memory" in gateway.log(), WAIT + 15),
            gateway.log()[-800:])
    broker.start()
    t.check("and is replayed from there once the broker is back",
            wait_until(lambda: gateway.metric("tiltgate_store_records", feed="mqtt") == 0 and
                       not kept(state_dir), REPLAY_WAIT), store_metrics(gateway))
    gateway.stop()


def sparkplug_on_a_full_disk(t, tiltgate, source, broker, sim, disk):
    codec = spb_codec.Codec(source, t.dir)
    observer = Observer(broker, codec, client_id="disk-observer")
    observer.start()
    state_dir = os.path.join(disk.path, "state")
    os.makedirs(state_dir)
    disk.fill()
    gateway = Gateway(tiltgate, t.dir, sim, {
        "host": "127.0.0.1", "port": broker.port, "group_id": "plant40", "edge_node_id": "gw40",
        "client_id": "tg-e2e-disk-spb", "keepalive_s": 5, "state_dir": state_dir,
        "on_change_deg": 0.0, "min_interval_ms": 0, "max_interval_ms": 1000,
    }, sensor_keys={"poll_ms": 100}, name="spb-gw")
    t.logs.append(("sparkplug gateway", gateway.log_path))
    gateway.start()
    birth = observer.wait_for(WAIT, "NBIRTH")
    t.check("with bdSeq refused by the full disk the edge node connects all the same: NBIRTH",
            birth, gateway.log()[-1500:])
    t.check("and says bdSeq was not stored, and why",
            "bdSeq 0 not stored" in gateway.log() and "No space left" in gateway.log(),
            gateway.log()[-800:])
    broker.stop()
    t.check("the DDATA of an outage on the full disk are kept (in memory), none uncounted",
            wait_until(lambda: gateway.metric("tiltgate_store_records", 0, feed="sparkplug") > 20,
                       WAIT) and gateway.metric("tiltgate_store_dropped_total", feed="sparkplug")
            == 0, {k: v for k, v in gateway.metrics().items() if "store" in k})
    since = observer.count()
    broker.start()
    t.check("and replayed once the broker is back: tiltgate_store_records{feed=\"sparkplug\"} 0",
            wait_until(lambda: gateway.metric("tiltgate_store_records", feed="sparkplug") == 0,
                       REPLAY_WAIT) and observer.wait_for(WAIT, "DDATA", since=since),
            {k: v for k, v in gateway.metrics().items() if "store" in k})
    disk.free()
    t.check("once the disk has room the store says it writes again",
            wait_until(lambda: "the disk takes writes again" in gateway.log(), WAIT),
            gateway.log()[-800:])
    gateway.stop()
    observer.close()


def scenario(t):
    tiltgate, source = arguments()
    disks = []
    try:
        broker = Broker(t.dir, keep_sessions=True)
        t.logs.append(("broker", broker.log_path))
        broker.start()
        sim = Simulator(tiltgate, t.dir)
        t.logs.append(("simulator", sim.err_path))
        disks.append(SmallDisk(os.path.join(t.dir, "mqtt-disk"), 1024))
        state_dir = mqtt_replay_on_a_full_disk(t, tiltgate, broker, sim, disks[-1])
        lost_to_a_corrupt_record(t, tiltgate, broker, sim, state_dir)
        state_dir_usable_later(t, tiltgate, broker, sim)
        disks.append(SmallDisk(os.path.join(t.dir, "spb-disk"), 1024))
        sparkplug_on_a_full_disk(t, tiltgate, source, broker, sim, disks[-1])
    finally:
        for disk in disks:
            disk.unmount()


if __name__ == "__main__":
    sys.exit(Checks("store-disk").run(scenario))
