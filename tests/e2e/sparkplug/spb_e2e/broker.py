"""A mosquitto of the test's own on a free loopback port, never a system broker, logging every
packet (log_type all): the log shows each CONNECT (clean session, will QoS and retain), SUBSCRIBE
and PUBLISH in the order the broker received them. With `keep_sessions`, the broker saves its
sessions when it stops and queues QoS 0 messages for a subscriber that is away, so an observer
with a persistent session misses nothing while the broker restarts."""
import os
import re
import shutil
import subprocess

from . import processes


def mosquitto_path():
    return shutil.which("mosquitto") or "/usr/sbin/mosquitto"


class Broker:
    def __init__(self, scratch_dir, keep_sessions=False):
        self.port = processes.free_port()
        self.log_path = os.path.join(scratch_dir, "broker.log")
        self.config_path = os.path.join(scratch_dir, "broker.conf")
        lines = [
            "listener %d 127.0.0.1" % self.port,
            "allow_anonymous true",
            "log_dest stderr",
            "log_type all",
            "connection_messages true",
            # Started as root, mosquitto otherwise switches to its own user, which may not read
            # /etc/hosts.allow (see tests/e2e/mqtt_feed_test.sh).
            "user root",
        ]
        if keep_sessions:
            persistence = os.path.join(scratch_dir, "broker-db") + "/"
            os.makedirs(persistence, exist_ok=True)
            lines += ["persistence true", "persistence_location " + persistence,
                      "queue_qos0_messages true", "max_queued_messages 0"]
        else:
            lines.append("persistence false")
        with open(self.config_path, "w") as f:
            f.write("\n".join(lines) + "\n")
        self.process = None

    def start(self):
        log = open(self.log_path, "a")
        self.process = processes.start([mosquitto_path(), "-c", self.config_path],
                                       stdout=log, stderr=subprocess.STDOUT)
        if not processes.wait_until(self._answers, 10):
            raise RuntimeError("mosquitto did not start:\n" + processes.tail(self.log_path))

    def stop(self):
        self.process.terminate()
        self.process.wait(timeout=10)

    def _answers(self):
        return subprocess.run(["mosquitto_pub", "-h", "127.0.0.1", "-p", str(self.port),
                               "-t", "probe", "-n"], capture_output=True).returncode == 0

    def log(self):
        with open(self.log_path, errors="replace") as f:
            return f.read()

    def log_lines(self):
        return self.log().splitlines()

    def connects(self, client_id):
        """Every CONNECT of `client_id`: (line index, clean session flag)."""
        pattern = re.compile(r"New client connected from \S+ as (\S+) \(p\d+, c(\d)")
        found = []
        for i, line in enumerate(self.log_lines()):
            m = pattern.search(line)
            if m and m.group(1) == client_id:
                found.append((i, m.group(2) == "1"))
        return found

    def publishes_after_last_connect(self, client_id):
        """The PUBLISH packets the broker received from `client_id` since its last CONNECT:
        (dup flag, topic) each."""
        connect = re.compile(r"New client connected from \S+ as (\S+) ")
        publish = re.compile(r"Received PUBLISH from (\S+) \(d(\d), q\d, r\d, m\d+, '([^']*)'")
        found = []
        for line in self.log_lines():
            m = connect.search(line)
            if m and m.group(1) == client_id:
                found = []
                continue
            m = publish.search(line)
            if m and m.group(1) == client_id:
                found.append((m.group(2) == "1", m.group(3)))
        return found

    def events(self, client_id):
        """What the broker received from `client_id`, in order: ("connect", clean_session),
        ("will", topic, qos, retain), ("subscribe", topic, qos), ("publish", topic, qos, retain)
        and ("disconnected",). The broker logs each packet's lines together: a header line, then
        the will's topic or the subscriptions on tab-indented lines."""
        connect = re.compile(r"New client connected from \S+ as (\S+) \(p\d+, c(\d)")
        will = re.compile(r"Will message specified \(\d+ bytes\) \(r(\d), q(\d)\)")
        subscribe = re.compile(r"Received SUBSCRIBE from (\S+)$")
        publish = re.compile(r"Received PUBLISH from (\S+) \(d\d, q(\d), r(\d), m\d+, '([^']*)'")
        gone = re.compile(r"Client (\S+) (disconnected|closed its connection|has exceeded)")
        header = re.compile(r"^(Received|Sending|New |Client |No will|Will message|Socket error)")
        events = []
        connected = None  # the client of the last CONNECT line
        context = None  # ("will", retain, qos) or ("subscribe",) while its lines go on
        for line in self.log_lines():
            text = line.split(": ", 1)[1] if ": " in line else line
            if text.startswith("\t"):
                item = text.strip()
                if context and context[0] == "will":
                    events.append(("will", item, context[2], context[1]))
                    context = None
                elif context and context[0] == "subscribe":
                    m = re.match(r"(.*) \(QoS (\d)\)$", item)
                    if m:
                        events.append(("subscribe", m.group(1), int(m.group(2))))
                continue
            if not header.search(text):
                continue
            context = None
            m = connect.search(text)
            if m:
                connected = m.group(1)
                if connected == client_id:
                    events.append(("connect", m.group(2) == "1"))
                continue
            m = will.search(text)
            if m and connected == client_id:
                context = ("will", m.group(1) == "1", int(m.group(2)))
                continue
            m = subscribe.search(text)
            if m and m.group(1) == client_id:
                context = ("subscribe",)
                continue
            m = publish.search(text)
            if m and m.group(1) == client_id:
                events.append(("publish", m.group(4), int(m.group(2)), m.group(3) == "1"))
                continue
            m = gone.search(text)
            if m and m.group(1) == client_id:
                events.append(("disconnected",))
        return events
