"""Modbus TCP, just enough for the scripts that read the gateway themselves (scripts/soak.py,
bench/bus_gateway.py): one request at a time on an open socket."""
import struct


def modbus_call(sock, unit, pdu, tid=[0]):
    """Sends one request PDU to `unit` and returns the reply PDU (function code first)."""
    tid[0] = (tid[0] + 1) & 0xFFFF
    sock.sendall(struct.pack(">HHHB", tid[0], 0, len(pdu) + 1, unit) + pdu)
    header = recv_exact(sock, 7)
    _, _, length, _ = struct.unpack(">HHHB", header)
    return recv_exact(sock, length - 1)


def recv_exact(sock, n):
    data = b""
    while len(data) < n:
        chunk = sock.recv(n - len(data))
        if not chunk:
            raise ConnectionError("closed")
        data += chunk
    return data


def read_input(sock, unit, address, count_):
    """Function 04: the registers' values; an exception reply raises ValueError."""
    reply = modbus_call(sock, unit, struct.pack(">BHH", 4, address, count_))
    if reply[0] & 0x80:
        raise ValueError(f"exception {reply[1]:02X}")
    return struct.unpack(f">{count_}H", reply[2:2 + 2 * count_])
