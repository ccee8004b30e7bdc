#!/usr/bin/env python3
"""`tiltgate demo --sparkplug-host 127.0.0.1` publishes the demo's simulated sensors as a
Sparkplug B edge node (issue 28, "Tests"): an NBIRTH, a DBIRTH for every sensor the demo serves
(its /api/sensors names) and DDATA that follow, decoded by protoc's Python output; the Modbus
RTU inclinometer's Properties carry the serial, firmware and model its profile's [identity]
names (issue 41).

Usage: /usr/bin/python3 demo_test.py path/to/tiltgate
"""
import json
import os
import subprocess
import sys
import urllib.request

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from spb_e2e import codec as spb_codec  # noqa: E402
from spb_e2e import processes  # noqa: E402
from spb_e2e.broker import Broker  # noqa: E402
from spb_e2e.checks import Checks, arguments  # noqa: E402
from spb_e2e.observer import Observer  # noqa: E402
from spb_e2e.processes import wait_until  # noqa: E402
from spb_e2e.tahu import check_decoders  # noqa: E402
from spb_e2e.sparkplug import birth_value, device_views, seq_violations  # noqa: E402

WAIT = 20


def scenario(t):
    tiltgate, source = arguments()
    codec = spb_codec.Codec(source, t.dir)
    broker = Broker(t.dir)
    t.logs.append(("broker", broker.log_path))
    broker.start()
    observer = Observer(broker, codec)
    observer.start()
    http_port = processes.free_port()
    log_path = os.path.join(t.dir, "demo.log")
    t.logs.append(("demo", log_path))
    # The demo writes its private files under TMPDIR: the test's folder.
    env = dict(os.environ, TMPDIR=t.dir)
    demo = processes.start(
        [tiltgate, "demo", "--port", str(processes.free_port()), "--http-port", str(http_port),
         "--no-accounts",
         "--sparkplug-host", "127.0.0.1", "--sparkplug-port", str(broker.port)],
        stdout=open(log_path, "w"), stderr=subprocess.STDOUT, env=env, cwd=t.dir)

    def sensors():
        if demo.poll() is not None:
            raise RuntimeError("the demo exited with %d:\n%s" %
                               (demo.returncode, processes.tail(log_path)))
        try:
            return json.loads(urllib.request.urlopen(
                "http://127.0.0.1:%d/api/sensors" % http_port, timeout=2).read())
        except OSError:
            return None
    served = wait_until(sensors, WAIT)
    names = sorted(s["name"] for s in served or [])
    t.check("the demo serves its sensors", len(names) >= 2, names)
    nbirth = observer.wait_for(WAIT, "NBIRTH")
    t.check("tiltgate demo --sparkplug-host publishes an NBIRTH", nbirth, processes.tail(log_path))
    born = wait_until(lambda: {m.device for m in observer.messages("DBIRTH")} >= set(names),
                      WAIT)
    t.check("a DBIRTH for every demo sensor", born and names,
            (names, sorted({m.device for m in observer.messages("DBIRTH")})))
    flowing = wait_until(lambda: {m.device for m in observer.messages("DDATA")} >= set(names),
                         WAIT)
    t.check("DDATA for every demo sensor (the demo's angles sway)", flowing and names,
            sorted({m.device for m in observer.messages("DDATA")}))
    if nbirth:
        group = nbirth.topic.split("/")[1]
        t.check("every message is in the NBIRTH's group and edge node",
                all(m.topic.split("/")[1] == group and
                    m.topic.split("/")[3] == nbirth.topic.split("/")[3]
                    for m in observer.messages()), nbirth.topic)
    rtu = "rtu-inclinometer"  # the demo's Modbus RTU device, read through the example profile
    # the model is the profile's model_name; serial and firmware its [identity] values
    expected = ("20240917", "1.02", "RTU inclinometer")

    def rtu_identity():
        births = observer.messages("DBIRTH", rtu)
        if not births:
            return None
        _, data = device_views(observer.messages(), rtu)

        def latest(name):  # the last DDATA's, else the DBIRTH's
            values = [n[name]["value"] for _, n in data if name in n]
            return values[-1] if values else birth_value(births[-1], name)
        got = tuple(latest("Properties/" + k) for k in ("serial", "firmware", "model"))
        return got if got == expected else None
    t.check("the Modbus RTU device's Properties/serial, firmware and model are its profile's "
            "[identity] values and model_name", wait_until(rtu_identity, WAIT),
            (rtu in names, [m.metrics() for m in observer.messages("DBIRTH", rtu)][:1]))
    broken, _ = seq_violations(observer.messages())
    t.check("tck-id-payloads-sequence-num-incrementing: the demo's seq rule holds", not broken,
            broken[:3])
    check_decoders(t, observer, tiltgate, codec)
    since = observer.count()
    demo.terminate()
    t.check("Ctrl-C (SIGTERM) stops the demo cleanly", demo.wait(timeout=20) == 0)
    t.check("tck-id-operational-behavior-edge-node-intentional-disconnect-ndeath: the stopping "
            "demo publishes its NDEATH", observer.wait_for(WAIT, "NDEATH", since=since))
    left = [n for n in os.listdir(t.dir) if n.startswith("tiltgate-demo")]
    t.check("the demo's edge node state (bdSeq, store) stays in its private folder, removed at "
            "exit", not left, left)


if __name__ == "__main__":
    sys.exit(Checks("spb-demo").run(scenario))
