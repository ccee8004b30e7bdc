#!/usr/bin/env python3
"""The northbound feeds of a warm standby pair (docs/northbound.md, "MQTT" and "Sparkplug B";
docs/operations.md "Warm standby"): the two-master line of warm_standby_test.py, both gateways
with the same [mqtt] and [sparkplug] tables (one topic prefix, one group and edge node id, one
client id each), against a mosquitto of the test's own. A host must see one source of live data
and never two edge nodes of one id:

- while the primary is active, only it is connected: the broker sees one CONNECT of each client
  id, one NBIRTH, and the standby logs no feed started, not even after a reload (SIGHUP) that
  changes both tables;
- SIGKILL of the primary: the broker publishes its will (NDEATH, its bdSeq), then the standby
  takes the line and its own NBIRTH follows, with the bdSeq after the one in its state_dir
  (seeded with 41 here, so the NBIRTH says whose it is), its DBIRTHs, and JSON states again;
- the same process stands down and takes over again (SIGSTOP for longer than half
  takeover_ms: held up, it gives the line back, hears silence, takes it again): a clean NDEATH
  published by the edge node itself, then a new session with bdSeq + 1 and JSON states again.

Usage: /usr/bin/python3 standby_feeds_test.py path/to/tiltgate
"""
import os
import signal
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "support"))
import spb_path  # noqa: F401,E402
from mqtt_store_test import JsonObserver, mqtt_table  # noqa: E402
from spb_e2e import codec as spb_codec  # noqa: E402
from spb_e2e.broker import Broker  # noqa: E402
from spb_e2e.checks import Checks, arguments  # noqa: E402
from spb_e2e.observer import Observer  # noqa: E402
from spb_e2e.plant import toml_value  # noqa: E402
from spb_e2e.processes import wait_until  # noqa: E402
from spb_e2e.sparkplug import birth_value, topic  # noqa: E402
from standby_pair import TAKEOVER_MS, TwoMasterSim, make_pair, role, status  # noqa: E402

GROUP, NODE = "pair", "gw"
JSON_CLIENT, SPB_CLIENT = "tg-pair-json", "tg-pair-spb"
SEEDED_BD_SEQ = 41  # in the standby's state_dir before it starts
WAIT = 10  # seconds: generous, never a measurement
QUIET_S = 2.5  # how long the standby is watched for a CONNECT it must not make


def add_feeds(gateway, broker, state_dir):
    mqtt = mqtt_table(broker, state_dir, JSON_CLIENT)
    sparkplug = {"host": "127.0.0.1", "port": broker.port, "group_id": GROUP,
                 "edge_node_id": NODE, "client_id": SPB_CLIENT, "keepalive_s": 5,
                 "state_dir": state_dir, "min_interval_ms": 100, "max_interval_ms": 1000}
    with open(gateway.config_path, "a") as f:
        for table, keys in (("mqtt", mqtt), ("sparkplug", sparkplug)):
            f.write("\n[%s]\n" % table)
            f.write("".join("%s = %s\n" % (k, toml_value(v)) for k, v in keys.items()))


def reload(gateway):
    """SIGHUP; true once the log says the file was reloaded once more."""
    done = lambda: gateway.log(10 ** 7).count("configuration reloaded from")
    before = done()
    gateway.process.send_signal(signal.SIGHUP)
    return wait_until(lambda: done() > before, WAIT)


def bd_seq(message):
    return birth_value(message, "bdSeq") if message else None


def sent_ndeath(broker):
    """NDEATHs the edge node published itself (not the broker's will)."""
    return [e for e in broker.events(SPB_CLIENT)
            if e[0] == "publish" and e[1] == topic(GROUP, NODE, "NDEATH")]


def scenario(t):
    tiltgate, source = arguments()
    codec = spb_codec.Codec(source, t.dir)
    broker = Broker(t.dir)
    t.logs.append(("broker", broker.log_path))
    broker.start()
    host = Observer(broker, codec, client_id="host")
    host.start()
    feed = JsonObserver(broker)
    feed.start()
    sim = TwoMasterSim(tiltgate, t.dir)
    t.logs.append(("simulator", sim.err_path))
    primary, standby = make_pair(t, tiltgate, sim)
    for name, gateway in (("primary", primary), ("standby", standby)):
        add_feeds(gateway, broker, os.path.join(t.dir, name, "state"))
    os.makedirs(os.path.join(t.dir, "standby", "state", "sparkplug"))
    with open(os.path.join(t.dir, "standby", "state", "sparkplug", "bdSeq"), "w") as f:
        f.write("%d\n" % SEEDED_BD_SEQ)

    primary.start()
    t.check("the primary takes the line", wait_until(lambda: role(primary) == "active", WAIT),
            (status(primary), primary.log()))
    first = host.wait_for(WAIT, "NBIRTH")
    t.check("the active primary's NBIRTH arrives (bdSeq 0, its first session)",
            bd_seq(first) == 0, (first, primary.log()))
    t.check("and its JSON states", wait_until(lambda: feed.states("s223"), WAIT))

    standby.start()
    t.check("the standby listens", wait_until(lambda: role(standby) == "standby", WAIT),
            status(standby))
    t.check("the standby serves what it hears",
            wait_until(lambda: standby.sensor("s223").get("online"), WAIT), standby.log())
    with open(standby.config_path) as f:
        text = f.read()
    with open(standby.config_path, "w") as f:  # both tables change: each would restart
        f.write(text.replace("interval_ms = 200", "interval_ms = 300")
                .replace("max_interval_ms = 1000", "max_interval_ms = 2000"))
    t.check("a reload of the standby changing [mqtt] and [sparkplug]", reload(standby),
            standby.log())
    time.sleep(QUIET_S)
    t.check("the broker saw one CONNECT of each client id: the primary's",
            (len(broker.connects(JSON_CLIENT)), len(broker.connects(SPB_CLIENT))) == (1, 1),
            (broker.connects(JSON_CLIENT), broker.connects(SPB_CLIENT)))
    t.check("one NBIRTH so far: the standby's edge node is not connected",
            len(host.messages("NBIRTH")) == 1, host.messages("NBIRTH"))
    t.check("the standby started neither feed",
            "MQTT feed to" not in standby.log(10 ** 7) and
            "Sparkplug edge node" not in standby.log(10 ** 7), standby.log())

    # SIGKILL the primary: its will, then the standby's session.
    since = host.count()
    primary.process.send_signal(signal.SIGKILL)
    killed_at = time.monotonic()
    t.check("the standby takes the line", wait_until(lambda: role(standby) == "active", WAIT),
            (status(standby), standby.log()))
    states_since = feed.count()  # the primary is long gone: what comes now is the standby's
    birth = host.wait_for(WAIT, "NBIRTH", since=since)
    t.check("the standby's NBIRTH arrives once it took over (%.1f s after the kill)"
            % (time.monotonic() - killed_at), birth, standby.log())
    t.check("its bdSeq is the one after its state_dir's (%d)" % (SEEDED_BD_SEQ + 1),
            bd_seq(birth) == SEEDED_BD_SEQ + 1, birth)
    will = host.wait_for(WAIT, "NDEATH", since=since)
    t.check("the killed primary's will (NDEATH, bdSeq 0) came before that NBIRTH",
            will and bd_seq(will) == 0 and birth and will.index < birth.index, (will, birth))
    if birth:
        t.check("DBIRTHs of both sensors follow it",
                all(host.wait_for(WAIT, "DBIRTH", d, since=birth.index) for d in ("s223", "s224")))
    t.check("JSON states flow from the standby (a second CONNECT of the feed's client id)",
            wait_until(lambda: feed.states("s224", since=states_since) and
                       len(broker.connects(JSON_CLIENT)) == 2, WAIT),
            broker.connects(JSON_CLIENT))

    # The same process stands down and takes over again.
    since = host.count()
    ndeaths = len(sent_ndeath(broker))
    os.kill(standby.process.pid, signal.SIGSTOP)
    time.sleep(TAKEOVER_MS * 0.8 / 1000)
    os.kill(standby.process.pid, signal.SIGCONT)
    t.check("held up, the active standby stands down",
            wait_until(lambda: status(standby).get("redundancy", {}).get("step_downs") == 1,
                       WAIT), status(standby))
    states_since = feed.count()  # its feed stopped as it stood down
    t.check("its edge node publishes NDEATH itself before disconnecting (bdSeq %d)"
            % (SEEDED_BD_SEQ + 1),
            wait_until(lambda: len(sent_ndeath(broker)) > ndeaths, WAIT) and
            bd_seq(host.wait_for(WAIT, "NDEATH", since=since)) == SEEDED_BD_SEQ + 1,
            host.messages("NDEATH", since=since))
    t.check("it takes the line again", wait_until(lambda: role(standby) == "active", WAIT),
            status(standby))
    again = host.wait_for(WAIT, "NBIRTH", since=since)
    t.check("a new session: NBIRTH with bdSeq %d" % (SEEDED_BD_SEQ + 2),
            bd_seq(again) == SEEDED_BD_SEQ + 2, (again, standby.log()))
    t.check("JSON states flow again (a third CONNECT)",
            wait_until(lambda: feed.states("s223", since=states_since) and
                       len(broker.connects(JSON_CLIENT)) == 3, WAIT),
            broker.connects(JSON_CLIENT))
    t.check("the gateway stops cleanly", standby.stop() == 0)


if __name__ == "__main__":
    sys.exit(Checks("standby-feeds").run(scenario))
