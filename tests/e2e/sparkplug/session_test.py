#!/usr/bin/env python3
"""The Sparkplug B edge node's session end to end (issue 28, "Tests"), one gateway run shared by
the scenarios, against a mosquitto of the test's own, decoded by protoc's Python output:
session establishment (clean session, the NDEATH will, NBIRTH contents, NCMD/DCMD subscribed
before the births), DBIRTH/DDATA values and timestamps, DDEATH and DBIRTH for a sensor that
falls silent and answers again, commands on (DCMD writes reach the simulated sensor; refused and
malformed ones are counted), the seq rule over more than 256 messages, a rebirth without a
reconnect, NDEATH on kill -9 with the right bdSeq, bdSeq + 1 after a restart, and NDEATH
published by a clean stop. Check names carry the Sparkplug 3.0 normative statements' ids.

Usage: /usr/bin/python3 session_test.py path/to/tiltgate
"""
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
from spb_e2e.sparkplug import birth_value, device_views, seq_violations, topic  # noqa: E402

GROUP, NODE, CLIENT = "plant1", "gw1", "tg-e2e-session"
WAIT = 20  # seconds: generous, never a measurement
COMMANDS = "tiltgate_sparkplug_commands_total"


def now_ms():
    return int(time.time() * 1000)


def angle_matches(expected):
    return lambda value: value is not None and abs(value - expected) < 1e-6


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
    t.check("the simulator takes angle commands", sim.command("angle 223 12.5 -3.25") == "ok")
    sim.command("angle 101 -45")
    state_dir = os.path.join(t.dir, "state")
    gateway = Gateway(tiltgate, t.dir, sim, {
        "host": "127.0.0.1", "port": broker.port, "group_id": GROUP, "edge_node_id": NODE,
        "client_id": CLIENT, "keepalive_s": 5, "state_dir": state_dir, "on_change_deg": 0.0,
        "min_interval_ms": 50, "max_interval_ms": 1000, "commands": True,
    }, sensor_keys={"poll_ms": 100},
        # A silent sensor's failed poll holds the bus 150 ms, not 3 x 500: its neighbour is polled
        # meanwhile, and does not turn stale (which reads offline, and would give it a DDEATH).
        bus_keys={"retries": 0, "late_guard_ms": 100})
    t.logs.append(("gateway", gateway.log_path))
    gateway.start()

    nbirth = observer.wait_for(WAIT, "NBIRTH")
    if not t.check("an NBIRTH arrives", nbirth, gateway.log()[-2000:]):
        return
    births = {d: observer.wait_for(WAIT, "DBIRTH", d) for d in ("boom", "mast")}
    t.check("a DBIRTH arrives for every sensor", all(births.values()), births)
    establishment(t, broker, nbirth)
    nbirth_contents(t, nbirth)
    for device, birth in births.items():
        if birth:
            dbirth_contents(t, device, birth, nbirth)
    data_values(t, observer, sim, gateway)
    silent_and_back(t, observer, sim)
    commands_on(t, observer, sim, gateway, codec)
    seq_order(t, observer, broker)
    rebirth(t, observer, broker, codec, nbirth)
    restarts(t, observer, broker, gateway, nbirth)
    nothing_retained(t, observer)
    check_decoders(t, observer, tiltgate, codec)


def establishment(t, broker, nbirth):
    events = broker.events(CLIENT)
    connects = [e for e in events if e[0] == "connect"]
    t.check("tck-id-principles-persistence-clean-session-311: the CONNECT asks a clean session",
            connects and connects[0][1], events[:5])
    wills = [e for e in events if e[0] == "will"]
    t.check("tck-id-message-flow-edge-node-birth-publish-will-message-topic: the CONNECT carries a "
            "will on the NDEATH topic",
            wills and wills[0][1] == topic(GROUP, NODE, "NDEATH"), wills)
    t.check("tck-id-message-flow-edge-node-birth-publish-will-message-qos: the will is QoS 1",
            wills and wills[0][2] == 1, wills)
    t.check("tck-id-message-flow-edge-node-birth-publish-will-message-will-retained: the will is "
            "not retained",
            wills and wills[0][3] is False, wills)
    first_publish = next((i for i, e in enumerate(events) if e[0] == "publish"), len(events))
    subscribed = [e[1] for e in events[:first_publish] if e[0] == "subscribe" and e[2] == 1]
    dcmd = topic(GROUP, NODE, "DCMD")
    t.check("tck-id-message-flow-edge-node-ncmd-subscribe: NCMD subscribed (QoS 1) before NBIRTH",
            topic(GROUP, NODE, "NCMD") in subscribed, events[:first_publish + 1])
    t.check("tck-id-message-flow-device-dcmd-subscribe: DCMD subscribed (QoS 1) before the births",
            any(s in (dcmd + "/+", dcmd + "/#") for s in subscribed) or
            all(dcmd + "/" + d in subscribed for d in ("boom", "mast")), subscribed)
    published = events[first_publish] if first_publish < len(events) else None
    t.check("tck-id-topics-nbirth-mqtt: the first PUBLISH is the NBIRTH, QoS 0, not retained",
            published == ("publish", topic(GROUP, NODE, "NBIRTH"), 0, False), published)
    t.check("the observer sees the NBIRTH not retained, QoS 0", not nbirth.retain and
            nbirth.qos == 0, nbirth)


def nbirth_contents(t, nbirth):
    bd_seq = nbirth.metric("bdSeq")
    rebirth = nbirth.metric("Node Control/Rebirth")
    t.check("tck-id-payloads-nbirth-seq: the NBIRTH's seq is 0", nbirth.seq == 0, nbirth.seq)
    t.check("tck-id-payloads-nbirth-timestamp: the NBIRTH has a timestamp",
            nbirth.payload["timestamp"] and nbirth.payload["timestamp"] > 1.6e12, nbirth.payload)
    t.check("tck-id-payloads-nbirth-bdseq: bdSeq is an Int64 metric, 0 on the first connect",
            bd_seq and bd_seq["datatype"] == spb_codec.INT64 and bd_seq["value"] == 0, bd_seq)
    t.check("tck-id-payloads-nbirth-rebirth-req: Node Control/Rebirth is Boolean false",
            rebirth and rebirth["datatype"] == spb_codec.BOOLEAN and rebirth["value"] is False,
            rebirth)
    version = nbirth.metric("Properties/version")
    buses = nbirth.metric("Properties/buses")
    t.check("the NBIRTH carries the node's info: version (String) and buses (UInt32) = 1",
            version and version["datatype"] == spb_codec.STRING and version["value"] and
            buses and buses["datatype"] == spb_codec.UINT32 and buses["value"] == 1,
            nbirth.metrics())


def dbirth_contents(t, device, birth, nbirth):
    names = {m["name"]: m for m in birth.metrics()}
    want = {"angle_x": spb_codec.DOUBLE, "tilt": spb_codec.DOUBLE, "status": spb_codec.UINT16,
            "online": spb_codec.BOOLEAN, "stale": spb_codec.BOOLEAN, "wrong_device": spb_codec.BOOLEAN,
            "alarms": spb_codec.UINT16, "alarms_danger": spb_codec.UINT16,
            "alarms_latched": spb_codec.UINT16, "relative_x": spb_codec.DOUBLE,
            "age_ms": spb_codec.INT64, "Properties/model": spb_codec.STRING,
            "Properties/serial": spb_codec.STRING, "Properties/firmware": spb_codec.STRING}
    if device == "boom":
        want["angle_y"] = spb_codec.DOUBLE
        want["relative_y"] = spb_codec.DOUBLE
    types = {n: names[n]["datatype"] if n in names else None for n in want}
    t.check("tck-id-topics-dbirth-metrics: %s's DBIRTH has every metric with its datatype" % device,
            types == want, types)
    if device == "mast":
        t.check("a single-axis sensor's DBIRTH has no angle_y", "angle_y" not in names, names)
    t.check("%s's DBIRTH: no temperature (a Rieker reports none) and no displacement (no lever_m)"
            % device, "temperature" not in names and "displacement_mm" not in names, names)
    units = {n: names[n]["properties"].get("engUnit") for n in ("angle_x", "tilt") if n in names}
    t.check("%s's angles carry the property engUnit deg" % device,
            units == {"angle_x": "deg", "tilt": "deg"}, units)
    aliases = [m["alias"] for m in birth.metrics()]
    t.check("tck-id-payloads-alias-birth-requirement: every DBIRTH metric has a name and an alias",
            all(a is not None for a in aliases) and all(names), birth.metrics())
    t.check("%s's DBIRTH: model is the configured one" % device,
            birth_value(birth, "Properties/model") == {"boom": "h6", "mast": "h4360"}[device],
            birth_value(birth, "Properties/model"))
    t.check("tck-id-payloads-dbirth-seq: %s's DBIRTH follows the NBIRTH in seq" % device,
            birth.index > nbirth.index and birth.seq is not None and 0 < birth.seq, birth.seq)
    settings = [n for n in names if n.startswith("Settings/")]
    t.check("%s's DBIRTH lists its writable settings (Settings/filter, Settings/zero_x)" % device,
            {"Settings/filter", "Settings/zero_x"} <= set(settings), settings)


def data_values(t, observer, sim, gateway):
    """DDATA by alias with the simulator's angles and the readings' timestamps."""
    def boom_at(x, y, since=0):
        def match():
            _, data = device_views(observer.messages(), "boom")
            for message, named in data:
                if message.index >= since and angle_matches(x)(named.get("angle_x", {}).get(
                        "value")) and angle_matches(y)(named.get("angle_y", {}).get("value")):
                    return message, named
            return None
        return wait_until(match, WAIT)
    first = boom_at(12.5, -3.25)
    t.check("DDATA carries the simulator's angles (boom 12.5, -3.25)", first,
            observer.messages("DDATA", "boom")[-3:])
    def mast_at_minus_45():
        _, data = device_views(observer.messages(), "mast")
        return [n for _, n in data if angle_matches(-45)(n.get("angle_x", {}).get("value"))]
    # Waited for: on a busy machine the mast's DDATA may come after the boom's.
    t.check("DDATA carries the single-axis simulator's angle (mast -45)",
            wait_until(mast_at_minus_45, WAIT), device_views(observer.messages(), "mast")[1][-2:])
    since = observer.count()
    set_at = now_ms()
    sim.command("angle 223 20.25 5.5")
    moved = boom_at(20.25, 5.5, since)
    if not t.check("a new angle on the simulator shows in the next DDATA", moved,
                   observer.messages("DDATA", "boom")[-3:]):
        return
    message, named = moved
    stamps = [m["timestamp"] for m in message.metrics()]
    t.check("tck-id-payloads-alias-data-cmd-requirement: DDATA metrics by alias, without names",
            all(m["name"] is None and m["alias"] is not None for m in message.metrics()) and
            None not in named, message.metrics())
    t.check("tck-id-payloads-name-birth-data-requirement: every DDATA metric has a timestamp",
            all(s is not None for s in stamps), message.metrics())
    reading = named["angle_x"]["timestamp"]
    t.check("the angle's timestamp is its reading's: after the angle changed, not after the "
            "message", set_at <= reading <= message.payload["timestamp"],
            (set_at, reading, message.payload["timestamp"]))
    age = named.get("age_ms", {}).get("value")
    # The message says when it left, the metric when its reading was taken, age_ms how old that
    # reading was when sampled for it: the three agree (to a few ms of the two clocks the gateway
    # takes them from), so the metric's time is the reading's, not the message's.
    t.check("a DDATA's metric timestamp is its reading's: the message's time less age_ms",
            age is not None and abs(message.payload["timestamp"] - reading - age) <= 100,
            (message.payload["timestamp"], reading, age))
    api = gateway.sensor_api("boom")
    _, data = device_views(observer.messages(), "boom")
    serials = [n["Properties/serial"]["value"] for _, n in data if "Properties/serial" in n]
    birth = observer.messages("DBIRTH", "boom")[0]
    serial = serials[-1] if serials else birth_value(birth, "Properties/serial")
    t.check("the sensor's serial (DBIRTH, or DDATA once read) is the one the API shows",
            serial and serial == api.get("serial"), (serial, api.get("serial")))


def silent_and_back(t, observer, sim):
    since = observer.count()
    sim.command("silent 223")
    ddeath = observer.wait_for(WAIT, "DDEATH", "boom", since)
    if not t.check("tck-id-operational-behavior-device-ddeath: a sensor that falls silent gets "
                   "a DDEATH", ddeath, observer.messages(device="boom", since=since)[-3:]):
        sim.command("answer 223")
        return
    t.check("tck-id-topics-ddeath-seq-num: the DDEATH has a seq", ddeath.seq is not None, ddeath)
    t.check("the other sensor stays born: no DDEATH for mast",
            not observer.messages("DDEATH", "mast", since))
    since = observer.count()
    answer_at = now_ms()
    sim.command("answer 223")
    dbirth = observer.wait_for(WAIT, "DBIRTH", "boom", since)
    if t.check("the sensor answers again: a new DBIRTH", dbirth,
               observer.messages(device="boom", since=since)[-3:]):
        online = dbirth.metric("online")
        angle = dbirth.metric("angle_x")
        t.check("the new DBIRTH says online, with a reading taken after it answered",
                online and online["value"] is True and angle and
                angle["timestamp"] >= answer_at and angle_matches(20.25)(angle["value"]),
                (online, angle, answer_at))
    between = [m for m in observer.messages("DDATA", "boom", ddeath.index)
               if not dbirth or m.index < dbirth.index]
    t.check("no DDATA between the DDEATH and the next DBIRTH", not between, between[:3])


def commands_on(t, observer, sim, gateway, codec):
    birth = observer.messages("DBIRTH", "boom")[-1]
    zero_alias = birth.metric("Settings/zero_x")["alias"] if birth.metric("Settings/zero_x") \
        else None
    dcmd = topic(GROUP, NODE, "DCMD", "boom")
    since = observer.count()
    # By alias, as tck-id-payloads-alias-data-cmd-requirement asks of a host.
    observer.publish(dcmd, codec.command(now_ms(), [
        {"alias": zero_alias, "datatype": spb_codec.DOUBLE, "value": 1.0}]))

    def zeroed():
        _, data = device_views(observer.messages(), "boom")
        return any(m.index >= since and angle_matches(19.25)(n.get("angle_x", {}).get("value"))
                   for m, n in data)
    t.check("commands = true: DCMD Settings/zero_x = 1 (by alias) reaches the sensor: the next "
            "DDATA reads 20.25 - 1", wait_until(zeroed, WAIT),
            observer.messages("DDATA", "boom")[-2:])

    def setting_is(name, value):
        _, data = device_views(observer.messages(), "boom")
        values = [n[name]["value"] for m, n in data if m.index >= since and name in n]
        return values and abs(values[-1] - value) < 1e-9
    t.check("the written zero_x shows in DDATA as Settings/zero_x = 1",
            wait_until(lambda: setting_is("Settings/zero_x", 1.0), WAIT))
    observer.publish(dcmd, codec.command(now_ms(), [
        {"name": "Settings/filter", "datatype": spb_codec.DOUBLE, "value": 3.0}]))
    t.check("DCMD Settings/filter = 3 (by name) shows in DDATA as Settings/filter = 3",
            wait_until(lambda: setting_is("Settings/filter", 3.0), WAIT))
    # One record of the sensor's settings: what its holding registers and the API show too.
    def recorded():
        settings = gateway.sensor_api("boom").get("settings", {})
        return settings.get("filter") == 3 and settings.get("zero_x") == 1
    t.check("the DCMD's filter = 3 is in the sensor's settings record (/api/sensors/boom)",
            wait_until(recorded, WAIT), gateway.sensor_api("boom").get("settings"))
    t.check("/metrics counts the writes: tiltgate_sparkplug_commands_total{result=\"write\"} >= 2",
            wait_until(lambda: gateway.metric(COMMANDS, 0, result="write") >= 2, WAIT),
            {k: v for k, v in gateway.metrics().items() if "sparkplug" in k})
    # The audit trail's door for DCMDs (docs/operations.md, "The audit trail").
    t.check("each DCMD write is one audit record, door sparkplug, with its ACK",
            wait_until(lambda: gateway.metric("tiltgate_audit_records_total", 0,
                                              door="sparkplug", result="ack") >= 2, WAIT),
            {k: v for k, v in gateway.metrics().items() if "audit" in k})
    t.check("the record names the setting and who asked (the log's \"audit: door sparkplug\")",
            any("audit: door sparkplug" in line and "filter" in line and ": ack" in line
                for line in gateway.log().splitlines()),
            [line for line in gateway.log().splitlines() if "audit:" in line][-4:])
    refused_before = gateway.metric(COMMANDS, 0, result="refused")
    observer.publish(dcmd, codec.command(now_ms(), [
        {"name": "Settings/filter", "datatype": spb_codec.DOUBLE, "value": 9.0}]))
    t.check("a DCMD out of the setting's range (filter 9) is refused and counted",
            wait_until(lambda: gateway.metric(COMMANDS, 0, result="refused") > refused_before,
                       WAIT),
            {k: v for k, v in gateway.metrics().items() if "commands" in k})
    for _ in range(6):
        observer.publish(dcmd, codec.command(now_ms(), [
            {"name": "Settings/zero_x", "datatype": spb_codec.DOUBLE, "value": 1e12}]))
    t.check("seven refused DCMD writes are counted",
            wait_until(lambda: gateway.metric(COMMANDS, 0, result="refused") >= refused_before + 7,
                       WAIT),
            {k: v for k, v in gateway.metrics().items() if "commands" in k})
    refusals = [line for line in gateway.log().splitlines()
                if "DCMD write of" in line and "refused:" in line]
    t.check("a refused DCMD is logged at warn with why, throttled by count: the first five of "
            "the minute in full",
            len(refusals) == 5 and all("warn" in line for line in refusals) and
            any("zero_x = " in line and " on boom refused: " in line for line in refusals),
            refusals)
    t.check("a refused DCMD is never logged as if it were written",
            "DCMD writes" not in gateway.log() and
            not any("DCMD wrote zero_x" in line and "e+12" in line or "1000000000000" in line
                    for line in gateway.log().splitlines() if "DCMD wrote" in line),
            [l for l in gateway.log().splitlines() if "DCMD" in l][-10:])
    malformed_before = gateway.metric(COMMANDS, 0, result="malformed")
    observer.publish(topic(GROUP, NODE, "NCMD"), b"\xff\xff\xff\xff not protobuf")
    t.check("a malformed NCMD payload is counted (result=\"malformed\")",
            wait_until(lambda: gateway.metric(COMMANDS, 0, result="malformed") >
                       malformed_before, WAIT),
            {k: v for k, v in gateway.metrics().items() if "commands" in k})
    after = observer.count()
    t.check("the gateway goes on after the malformed payload",
            observer.wait_for(WAIT, "DDATA", since=after) and gateway.running())
    # A flood of 40 commands at once: taken at [sparkplug] max_commands_per_s (20 by default),
    # the rest waiting for their turns, none lost, and DDATA goes on meanwhile.
    malformed_before = gateway.metric(COMMANDS, 0, result="malformed")
    delayed_before = gateway.metric("tiltgate_sparkplug_commands_delayed_total", 0)
    after = observer.count()
    for _ in range(40):
        observer.publish(topic(GROUP, NODE, "NCMD"), b"\xff\xff\xff\xff not protobuf")
    t.check("a flood of 40 commands: every one taken (counted malformed), those beyond the rate "
            "after waiting for their turn (tiltgate_sparkplug_commands_delayed_total)",
            wait_until(lambda: gateway.metric(COMMANDS, 0, result="malformed") >=
                       malformed_before + 40, WAIT) and
            gateway.metric("tiltgate_sparkplug_commands_delayed_total", 0) > delayed_before,
            {k: v for k, v in gateway.metrics().items() if "commands" in k})
    t.check("/metrics: tiltgate_sparkplug_max_commands_per_second 20",
            gateway.metric("tiltgate_sparkplug_max_commands_per_second") == 20)
    t.check("DDATA goes on during the flood", observer.wait_for(WAIT, "DDATA", since=after))
    t.check("/metrics: tiltgate_sparkplug_connected 1 and tiltgate_sparkplug_published_total > 10",
            gateway.metric("tiltgate_sparkplug_connected") == 1 and
            gateway.metric("tiltgate_sparkplug_published_total", 0) > 10,
            {k: v for k, v in gateway.metrics().items() if "sparkplug" in k})


def seq_order(t, observer, broker):
    # The gateway's own messages: the commands the test published arrive here too.
    def own():
        return len([m for m in observer.messages() if m.type not in ("NCMD", "DCMD")])
    enough = wait_until(lambda: own() > 300, 40)
    t.check("over 300 messages of one session arrive (the seq wraps)", enough, own())
    broken, wraps = seq_violations(observer.messages())
    t.check("tck-id-payloads-sequence-num-incrementing: seq is 0 in the NBIRTH, then +1 per "
            "message in the order they arrive", not broken, broken[:5])
    t.check("tck-id-topics-ddata-seq-num: seq wraps from 255 to 0", wraps >= 1, wraps)
    wire = [e[1] for e in broker.events(CLIENT) if e[0] == "publish"]
    seen = [m.topic for m in observer.messages() if not m.topic.startswith("spBv1.0/STATE") and
            m.type not in ("NCMD", "DCMD")]
    t.check("the messages arrive in the order the gateway put them on the wire (broker log)",
            seen == wire[:len(seen)], (len(seen), len(wire)))


def rebirth(t, observer, broker, codec, first_nbirth):
    connects = len(broker.connects(CLIENT))
    since = observer.count()
    observer.publish(topic(GROUP, NODE, "NCMD"), codec.command(now_ms(), [
        {"name": "Node Control/Rebirth", "datatype": spb_codec.BOOLEAN, "value": True}]))
    nbirth = observer.wait_for(WAIT, "NBIRTH", since=since)
    if not t.check("tck-id-operational-behavior-data-commands-rebirth-action-2: NCMD Rebirth "
                   "gives a new NBIRTH", nbirth):
        return
    t.check("tck-id-operational-behavior-data-commands-rebirth-action-3: the rebirth's NBIRTH has "
            "the same bdSeq, and seq 0",
            nbirth.metric("bdSeq")["value"] == first_nbirth.metric("bdSeq")["value"] and
            nbirth.seq == 0, nbirth)
    t.check("tck-id-operational-behavior-data-commands-rebirth-action-2: every DBIRTH again",
            all(observer.wait_for(WAIT, "DBIRTH", d, nbirth.index) for d in ("boom", "mast")))
    t.check("a rebirth is without reconnecting: no new CONNECT, no NDEATH",
            len(broker.connects(CLIENT)) == connects and
            not observer.messages("NDEATH", since=since), broker.connects(CLIENT))


def restarts(t, observer, broker, gateway, first_nbirth):
    births = observer.messages("NBIRTH")
    bd_seq = births[-1].metric("bdSeq")["value"]
    since = observer.count()
    gateway.kill()
    ndeath = observer.wait_for(WAIT, "NDEATH", since=since)
    if t.check("tck-id-message-flow-edge-node-birth-publish-will-message: killed (kill -9), the "
               "broker sends the NDEATH will", ndeath):
        value = ndeath.metric("bdSeq")["value"] if ndeath.metric("bdSeq") else None
        t.check("tck-id-payloads-ndeath-bdseq: the NDEATH's bdSeq is the NBIRTH's",
                value == bd_seq, (value, bd_seq))
        t.check("tck-id-topics-ndeath-seq: the NDEATH has no seq; QoS 1, not retained",
                ndeath.seq is None and ndeath.qos == 1 and not ndeath.retain, ndeath)
    since = observer.count()
    gateway.start()
    nbirth = observer.wait_for(WAIT, "NBIRTH", since=since)
    if t.check("restarted on the same state_dir, the gateway births again", nbirth):
        value = nbirth.metric("bdSeq")["value"]
        t.check("tck-id-topics-nbirth-bdseq-increment: bdSeq + 1 after a restart (kept in "
                "state_dir)", value == (bd_seq + 1) % 256, (value, bd_seq))
    observer.wait_for(WAIT, "DBIRTH", "boom", since)
    since = observer.count()
    t.check("a clean stop (SIGTERM) exits 0", gateway.stop() == 0, gateway.log()[-1500:])
    ndeath = observer.wait_for(WAIT, "NDEATH", since=since)
    published = [e for e in broker.events(CLIENT) if e[0] == "publish" and "NDEATH" in e[1]]
    t.check("tck-id-operational-behavior-edge-node-intentional-disconnect-ndeath: a clean stop "
            "publishes NDEATH (QoS 1) itself, with this connection's bdSeq",
            ndeath and nbirth and published and published[-1][2] == 1 and
            ndeath.metric("bdSeq")["value"] == nbirth.metric("bdSeq")["value"],
            (ndeath, published[-1:]))


def nothing_retained(t, observer):
    retained = [m for m in observer.messages() if m.retain and m.type != "STATE"]
    t.check("tck-id-topics-nbirth-mqtt, -dbirth-mqtt, -ddata-mqtt: nothing the node publishes "
            "is retained", not retained, retained[:3])


if __name__ == "__main__":
    sys.exit(Checks("spb-session").run(scenario))
