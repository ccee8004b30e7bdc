"""A Sparkplug host's view of the broker: one MQTT 5 client subscribed to spBv1.0/# that records
every message with its topic, QoS, retain flag (retain-as-published, so it is the publisher's
flag) and decoded payload, in the order the broker delivered them. Its session persists
(session expiry), so with a broker that keeps sessions (broker.Broker(keep_sessions=True)) it
misses nothing while the broker restarts. Commands and STATE go out through publish()."""
import threading
import time

import paho.mqtt.client as mqtt
import paho.mqtt.publish
from paho.mqtt.packettypes import PacketTypes
from paho.mqtt.properties import Properties
from paho.mqtt.subscribeoptions import SubscribeOptions

from . import processes


class Message:
    def __init__(self, index, topic, qos, retain, payload, codec):
        self.index = index
        self.topic = topic
        self.qos = qos
        self.retain = retain
        self.raw = payload
        self.arrived = time.time()
        parts = topic.split("/")
        self.type = parts[2] if len(parts) > 2 and parts[1] != "STATE" else "STATE"
        self.device = parts[4] if len(parts) > 4 else None
        self.payload = None
        self.undecodable = None  # why the payload is not a Sparkplug B payload
        if self.type != "STATE":
            try:
                self.payload = codec.decode(payload)
            except Exception as e:  # a test's own malformed command, or the gateway's bug
                self.undecodable = "%s: %s" % (type(e).__name__, e)

    @property
    def seq(self):
        return self.payload["seq"] if self.payload else None

    def metrics(self):
        return self.payload["metrics"] if self.payload else []

    def metric(self, name):
        for m in self.metrics():
            if m["name"] == name:
                return m
        return None

    def __repr__(self):
        return "%d %s q%d r%d %s" % (self.index, self.topic, self.qos, int(self.retain),
                                     self.payload if self.payload else self.raw)


class Observer:
    def __init__(self, broker, codec, client_id="observer", topic="spBv1.0/#"):
        self.broker = broker
        self.codec = codec
        self.topic = topic
        self._lock = threading.Lock()
        self._messages = []
        self._subscribed = threading.Event()
        self.client = mqtt.Client(client_id=client_id, protocol=mqtt.MQTTv5)
        self.client.on_connect = self._on_connect
        self.client.on_subscribe = lambda *args: self._subscribed.set()
        self.client.on_message = self._on_message
        self.client.reconnect_delay_set(min_delay=0.1, max_delay=0.5)

    def start(self):
        properties = Properties(PacketTypes.CONNECT)
        properties.SessionExpiryInterval = 3600
        self.client.connect("127.0.0.1", self.broker.port, keepalive=5, clean_start=False,
                            properties=properties)
        self.client.loop_start()
        if not self._subscribed.wait(10):
            raise RuntimeError("the observer did not get its SUBACK")

    def close(self):
        self.client.loop_stop()
        self.client.disconnect()

    def _on_connect(self, client, userdata, flags, rc, properties=None):
        client.subscribe(self.topic, options=SubscribeOptions(qos=2, retainAsPublished=True))

    def _on_message(self, client, userdata, msg):
        with self._lock:
            self._messages.append(Message(len(self._messages), msg.topic, msg.qos, msg.retain,
                                          msg.payload, self.codec))

    def messages(self, type=None, device=None, since=0):
        """What arrived so far, from index `since`, of a message type and device if given."""
        with self._lock:
            found = self._messages[since:]
        return [m for m in found
                if (type is None or m.type == type) and (device is None or m.device == device)]

    def count(self):
        with self._lock:
            return len(self._messages)

    def wait_for(self, timeout_s, type=None, device=None, since=0, where=lambda m: True):
        """The first message from index `since` that matches, waiting up to the deadline."""
        def find():
            for m in self.messages(type, device, since):
                if where(m):
                    return m
            return None
        return processes.wait_until(find, timeout_s)

    def publish(self, topic, payload, qos=1, retain=False):
        paho.mqtt.publish.single(topic, payload, qos=qos, retain=retain, hostname="127.0.0.1",
                                 port=self.broker.port, client_id="test-host")
