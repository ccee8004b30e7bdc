#!/usr/bin/env python3
"""Reloads keep no descriptor (issue 40, item 2): each reload that changes [mqtt] or [sparkplug]
restarts that feed's client, and once it is stopped the old one is freed with its socket pair.
100 reloads of each kind against a real mosquitto, counting /proc/<pid>/fd before and after,
and /metrics' process_open_fds and process_max_fds beside them.

Usage: /usr/bin/python3 reload_descriptors_test.py path/to/tiltgate
"""
import os
import re
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "sparkplug"))
from spb_e2e.broker import Broker  # noqa: E402
from spb_e2e.checks import Checks, arguments  # noqa: E402
from spb_e2e.plant import Gateway, Simulator  # noqa: E402
from spb_e2e.processes import wait_until  # noqa: E402

RELOADS = 100
WAIT = 20


def open_fds(gateway):
    return len(os.listdir("/proc/%d/fd" % gateway.process.pid))


def reload_alternating(gateway, pattern, first, second):
    """RELOADS reloads, each flipping the key `pattern` matches between two values."""
    for i in range(RELOADS):
        with open(gateway.config_path) as f:
            text = f.read()
        value = second if i % 2 == 0 else first
        changed = re.sub(pattern, lambda m: m.group(1) + value, text, count=1)
        with open(gateway.config_path, "w") as f:
            f.write(changed)
        if not gateway.reload(WAIT):
            return False
    return True


def scenario(t):
    tiltgate, _ = arguments()
    broker = Broker(t.dir)
    t.logs.append(("broker", broker.log_path))
    broker.start()
    sim = Simulator(tiltgate, t.dir)
    t.logs.append(("simulator", sim.err_path))
    mqtt = {"host": "127.0.0.1", "port": broker.port, "client_id": "tg-fds",
            "topic_prefix": "e2e/fds", "interval_ms": 200, "keepalive_s": 5}
    sparkplug = {"host": "127.0.0.1", "port": broker.port, "group_id": "fds",
                 "edge_node_id": "gw", "state_dir": os.path.join(t.dir, "state"),
                 "keepalive_s": 5}
    gateway = Gateway(tiltgate, t.dir, sim, sparkplug, mqtt=mqtt)
    t.logs.append(("gateway", gateway.log_path))
    gateway.start()
    t.check("both feeds connect",
            wait_until(lambda: gateway.metric("tiltgate_mqtt_connected") == 1 and
                       gateway.metric("tiltgate_sparkplug_connected") == 1, WAIT),
            gateway.log()[-1500:])
    before = open_fds(gateway)
    t.check("/metrics shows process_open_fds, near what /proc counts",
            abs(gateway.metric("process_open_fds", -100) - open_fds(gateway)) <= 4,
            (gateway.metric("process_open_fds"), before))
    t.check("/metrics shows process_max_fds, the descriptor limit",
            gateway.metric("process_max_fds", 0) >= 64, gateway.metric("process_max_fds"))

    t.check("%d reloads that change [mqtt] are each carried out" % RELOADS,
            reload_alternating(gateway, r'(\[mqtt\][^\[]*interval_ms = )\d+', "200", "300"),
            gateway.log()[-1500:])
    t.check("the MQTT feed is connected after them",
            wait_until(lambda: gateway.metric("tiltgate_mqtt_connected") == 1, WAIT))
    # Freed once stopped: looked at each second.
    settled = lambda slack: wait_until(lambda: open_fds(gateway) <= before + slack, 5)
    t.check("after %d reloads of [mqtt] the gateway holds no more descriptors than before" % RELOADS,
            settled(2), (before, open_fds(gateway)))

    t.check("%d reloads that change [sparkplug] are each carried out" % RELOADS,
            reload_alternating(gateway, r'(\[sparkplug\][^\[]*keepalive_s = )\d+', "5", "6"),
            gateway.log()[-1500:])
    t.check("the edge node is connected after them",
            wait_until(lambda: gateway.metric("tiltgate_sparkplug_connected") == 1, WAIT))
    t.check("after %d reloads of [sparkplug] the gateway holds no more descriptors than before"
            % RELOADS, settled(2), (before, open_fds(gateway)))
    t.check("Modbus clients are still served: /healthz answers", gateway._healthy())
    t.check("the gateway stops cleanly", gateway.stop() == 0)


if __name__ == "__main__":
    sys.exit(Checks("reload-fds").run(scenario))
