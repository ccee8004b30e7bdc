"""A TCP relay that puts a network between the gateway and a device server: every chunk it reads
from one side is written to the other `delay_ms` later (each direction on its own, so a round
trip costs twice the delay), in order; and it can drop every connection at once, as a link that
goes down does. The kernel here has no netem qdisc, so this userspace relay is how a test adds
latency; it runs in a thread of the test's own process (asyncio), on a free loopback port.

    relay = DelayRelay(ser2net.port, delay_ms=30)
    relay.start()          # then port = "tcp://127.0.0.1:%d" % relay.port
    relay.drop()           # every connection reset; the next connect is relayed again
    relay.link_down()      # every connection reset, and each new one reset at once, until
    relay.link_up()        # the link is up again
    relay.stop()
"""
import asyncio
import socket
import threading
import time


class DelayRelay:
    def __init__(self, target_port, delay_ms, target_host="127.0.0.1"):
        self.target = (target_host, target_port)
        self.delay_s = delay_ms / 1000.0
        self.port = None
        self.accepted = 0  # connections taken since start
        self._loop = None
        self._server = None
        self._thread = None
        self._links = set()  # (client transport, server transport) of each open connection
        self._down = False

    def start(self):
        started = threading.Event()
        self._loop = asyncio.new_event_loop()

        async def serve():
            sock = socket.socket()
            sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
            sock.bind(("127.0.0.1", 0))
            self.port = sock.getsockname()[1]
            self._server = await asyncio.start_server(self._relay, sock=sock)
            started.set()

        def run():
            self._loop.run_until_complete(serve())
            self._loop.run_forever()

        self._thread = threading.Thread(target=run, name="delay-relay", daemon=True)
        self._thread.start()
        if not started.wait(5):
            raise RuntimeError("the relay did not start")

    def set_delay(self, delay_ms):
        """Applies to chunks read from now on."""
        self.delay_s = delay_ms / 1000.0

    def drop(self):
        """Resets every open connection (both sides), as a link that fails."""
        def reset():
            for pair in list(self._links):
                for writer in pair:
                    writer.transport.abort()
            self._links.clear()
        self._call(reset)

    def link_down(self):
        """Drops every connection and resets each new one at once, until link_up()."""
        self._down = True
        self.drop()

    def link_up(self):
        self._down = False

    def stop(self):
        if self._loop is None:
            return
        self.drop()

        async def shutdown():
            self._server.close()
            tasks = [t for t in asyncio.all_tasks() if t is not asyncio.current_task()]
            for task in tasks:
                task.cancel()
            await asyncio.gather(*tasks, return_exceptions=True)
        asyncio.run_coroutine_threadsafe(shutdown(), self._loop).result(5)
        self._loop.call_soon_threadsafe(self._loop.stop)
        self._thread.join(5)
        self._loop = None

    def _call(self, fn):
        done = threading.Event()

        def run():
            try:
                fn()
            finally:
                done.set()
        self._loop.call_soon_threadsafe(run)
        done.wait(5)

    async def _relay(self, client_reader, client_writer):
        self.accepted += 1
        if self._down:
            client_writer.transport.abort()
            return
        try:
            server_reader, server_writer = await asyncio.open_connection(*self.target)
        except OSError:
            client_writer.transport.abort()  # the far server refused: so does the relay
            return
        for writer in (client_writer, server_writer):
            writer.transport.get_extra_info("socket").setsockopt(
                socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
        pair = (client_writer, server_writer)
        self._links.add(pair)
        directions = [asyncio.ensure_future(self._direction(client_reader, server_writer)),
                      asyncio.ensure_future(self._direction(server_reader, client_writer))]
        # A reset on either side ends both: the other side is reset too.
        done, pending = await asyncio.wait(directions, return_when=asyncio.FIRST_EXCEPTION)
        if any(task.exception() for task in done):
            for writer in pair:
                writer.transport.abort()
        await asyncio.gather(*pending, return_exceptions=True)
        self._links.discard(pair)
        for writer in pair:
            writer.transport.abort()

    async def _direction(self, reader, writer):
        """Reads as bytes come and writes each chunk once its delay is up, in order; an end of
        stream travels with the same delay."""
        queue = asyncio.Queue()

        async def read():
            while True:
                data = await reader.read(65536)
                queue.put_nowait((time.monotonic() + self.delay_s, data))
                if not data:
                    return

        async def write():
            while True:
                due, data = await queue.get()
                wait = due - time.monotonic()
                if wait > 0:
                    await asyncio.sleep(wait)
                if not data:
                    writer.write_eof() if writer.can_write_eof() else writer.close()
                    return
                writer.write(data)
                await writer.drain()

        reading = asyncio.ensure_future(read())
        try:
            await write()
        finally:
            reading.cancel()
