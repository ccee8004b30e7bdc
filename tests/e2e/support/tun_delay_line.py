"""A delay line for IP packets, for a kernel without netem: a network namespace reached from here
through two TUN devices, one on each side, with this process carrying every packet from one to
the other `delay_ms` later. Unlike a TCP relay (delay_relay.py), the delay is the packets' own,
so the kernel's TCP round trip measure (TCP_INFO), which the gateway adds to its reply waits,
sees it, as it would on a slow network.

    line = TunDelayLine(delay_ms=30)   # needs root and /dev/net/tun
    line.start()                       # then run a server in line.netns on line.far_address
    ...
    line.stop()                        # the namespace and both devices removed
"""
import fcntl
import os
import select
import struct
import subprocess
import threading
import time
from collections import deque

import run_netns_mount

TUNSETIFF = 0x400454CA
IFF_TUN = 0x0001
IFF_NO_PI = 0x1000


def _run(*argv):
    done = subprocess.run(argv, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    if done.returncode != 0:
        raise OSError("%s: %s" % (" ".join(argv), done.stdout.strip()))


def _open_tun(name):
    fd = os.open("/dev/net/tun", os.O_RDWR)
    fcntl.ioctl(fd, TUNSETIFF, struct.pack("16sH", name.encode(), IFF_TUN | IFF_NO_PI))
    return fd


class TunDelayLine:
    def __init__(self, delay_ms):
        tag = "tgtun%d" % (os.getpid() % 100000)
        self.netns = tag
        self.near_device, self.far_device = tag + "a", tag + "b"
        subnet = "10.253.%d" % (os.getpid() % 250)
        self.near_address, self.far_address = subnet + ".1", subnet + ".2"
        self.delay_s = delay_ms / 1000.0
        self._fds = []
        self._stop = False
        self._thread = None
        self._netns_mounted_before = run_netns_mount.was_mounted()

    def start(self):
        """Makes the namespace and the devices; raises OSError, saying why, where it cannot."""
        try:
            for name in (self.near_device, self.far_device):
                self._fds.append(_open_tun(name))
            _run("ip", "netns", "add", self.netns)
            _run("ip", "addr", "add", self.near_address, "peer", self.far_address,
                 "dev", self.near_device)
            _run("ip", "link", "set", self.near_device, "up")
            # The far device keeps its file descriptor here when it moves to the namespace.
            _run("ip", "link", "set", self.far_device, "netns", self.netns)
            _run("ip", "-n", self.netns, "addr", "add", self.far_address, "peer",
                 self.near_address, "dev", self.far_device)
            _run("ip", "-n", self.netns, "link", "set", self.far_device, "up")
            _run("ip", "-n", self.netns, "link", "set", "lo", "up")
        except OSError:
            self.stop()
            raise
        self._thread = threading.Thread(target=self._carry, name="tun-delay", daemon=True)
        self._thread.start()

    def stop(self):
        self._stop = True
        if self._thread:
            self._thread.join(5)
            self._thread = None
        for fd in self._fds:
            os.close(fd)  # a TUN device goes with its last descriptor
        self._fds = []
        subprocess.run(["ip", "netns", "del", self.netns], stdout=subprocess.DEVNULL,
                       stderr=subprocess.DEVNULL)
        run_netns_mount.release(self._netns_mounted_before)

    def _carry(self):
        """Each packet read from one device is written to the other delay_s later, in order."""
        near, far = self._fds
        waiting = {near: deque(), far: deque()}  # read from this fd: (due, packet), oldest first
        other = {near: far, far: near}
        while not self._stop:
            now = time.monotonic()
            for source, queue in waiting.items():
                while queue and queue[0][0] <= now:
                    try:
                        os.write(other[source], queue.popleft()[1])
                    except OSError:
                        pass  # the device is down: a packet lost, as on a link
            dues = [q[0][0] for q in waiting.values() if q]
            timeout = max(0.0, min(dues) - time.monotonic()) if dues else 0.1
            readable, _, _ = select.select([near, far], [], [], min(timeout, 0.1))
            for fd in readable:
                try:
                    packet = os.read(fd, 65536)
                except OSError:
                    continue
                waiting[fd].append((time.monotonic() + self.delay_s, packet))
