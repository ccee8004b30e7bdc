#!/usr/bin/env python3
"""packaging/wireshark/tiltgate.lua in Debian's tshark: captures written here (pcapng, link
type 252, as capture/pcapng.cpp writes them, by a writer of the test's own) of the verified
frames of docs/protocols.md, one or more per documented function, request and reply, for
tiltgate_rieker, tiltgate_dyna_ascii and tiltgate_dyna9:

- each frame's Info column names its function and decodes its values (angles to the
  documented float32 values, addresses, EEPROM locations, ...);
- the good frames' CRC / LRC status is Good; a flipped byte, and the vendor examples that
  docs/protocols.md lists as wrong, are Bad with an expert error;
- short, truncated and otherwise malformed frames are marked malformed, never a Lua error;
- without a direction in the packet's flags, request and reply are guessed.

tshark is required (Debian's tshark package): without it the test fails, never skips.

Usage: python3 wireshark_dissector_test.py [path/to/build/tiltgate]  (the path is not used)
"""
import os
import shutil
import struct
import subprocess
import sys
import tempfile

SOURCE = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
DISSECTOR = os.path.join(SOURCE, "packaging", "wireshark", "tiltgate.lua")
OUT, IN, NONE = 2, 1, None  # epb_flags direction: outbound (request), inbound (reply), not given

passes = failures = 0


def check(name, ok, seen=""):
    global passes, failures
    if ok:
        passes += 1
        print("ok: " + name)
    else:
        failures += 1
        print("FAIL: %s\n  seen: %s" % (name, seen))
    return ok


# ---- pcapng (the pcapng draft; exported PDU tags of Wireshark's epan/exported_pdu.h) ----

def pad(data):
    return data + b"\0" * (-len(data) % 4)


def option(code, value):
    return struct.pack("<HH", code, len(value)) + pad(value)


def block(kind, body):
    body = pad(body)
    return struct.pack("<II", kind, 12 + len(body)) + body + struct.pack("<I", 12 + len(body))


def packet(number, proto, frame, direction, comment):
    name = pad(proto.encode())  # tag 12, the dissector's name, its length given padded
    pdu = struct.pack(">HH", 12, len(name)) + name + struct.pack(">HH", 0, 0) + frame
    micros = 1_700_000_000_000_000 + number * 2000
    body = struct.pack("<IIIII", 0, micros >> 32, micros & 0xFFFFFFFF, len(pdu), len(pdu))
    body = pad(body + pdu)
    if direction is not None:
        body += option(2, struct.pack("<I", direction))
    return block(6, body + option(1, comment.encode()) + option(0, b""))


def write_capture(path, frames):
    section = struct.pack("<IHHq", 0x1A2B3C4D, 1, 0, -1) + option(0, b"")
    interface = struct.pack("<HHI", 252, 0, 0) + option(0, b"")
    with open(path, "wb") as f:
        f.write(block(0x0A0D0D0A, section) + block(1, interface))
        for number, frame in enumerate(frames, 1):
            f.write(packet(number, frame.proto, frame.data, frame.direction, frame.comment))


# ---- checksums, computed here from the documents' definitions ----

def crc16_arc(data):
    """docs/protocols.md, "Rieker CRC16": 0x8005 reflected (0xA001), initial 0, no final xor."""
    crc = 0
    for byte in data:
        crc ^= byte
        for _ in range(8):
            crc = (crc >> 1) ^ 0xA001 if crc & 1 else crc >> 1
    return crc


def rieker(hex_without_crc):
    """A Rieker frame with its CRC, high byte first."""
    data = bytes.fromhex(hex_without_crc)
    return data + struct.pack(">H", crc16_arc(data))


def dyna_ascii(digits):
    """':' + digits + the note's LRC over the characters (docs/protocols.md, "Dyna LRC")."""
    return (":%s%02X\r\n" % (digits, -sum(digits.encode()) & 0xFF)).encode()


class Frame:
    def __init__(self, proto, data, direction, info, comment=None, status=None, malformed=False,
                 fields=None):
        self.proto, self.data, self.direction, self.info = proto, data, direction, info
        self.comment = comment or {OUT: "request", IN: "reply"}.get(direction, "")
        self.status = status  # CRC / LRC status: "1" good, "0" bad, None not checked
        self.malformed = malformed
        self.fields = fields or {}


def r(data, direction, info, status="1", **kw):
    if isinstance(data, str):
        data = bytes.fromhex(data.replace(" ", ""))
    return Frame("tiltgate_rieker", data, direction, info, status=status, **kw)


def a(text, direction, info, status="1", **kw):
    data = text if isinstance(text, bytes) else text.encode()
    return Frame("tiltgate_dyna_ascii", data, direction, info, status=status, **kw)


def n(data, direction, info, **kw):
    comment = "request; 9th bit set on the first 1 byte(s)" if direction == OUT else None
    return Frame("tiltgate_dyna9", data, direction, info, comment=comment, **kw)


X, Y = -0.79339599609375, 18.44384765625  # "Rieker verified frames": the Get Angle reply

# docs/protocols.md, "Rieker verified frames" (and the errata's corrected CRCs: 1810, 9BD4,
# B6C2), each function's request and the reply it gets.
RIEKER = [
    r("0065 0000 0002 02 00DF F727", OUT, "Request: addr 101, Set Address, new address 223"),
    r("0000 0065 0000 00 CC1E", IN, "Reply: addr 101, ACK to Set Address"),
    r("FFFC 0000 0003 00 C31B", OUT, "Request: addr 65532 (broadcast), Get Address"),
    r("0000 00DF 0003 02 00DF 73F3", IN, "Reply: addr 223, Get Address, address 223"),
    r("00DF 0000 0004 00 AF11", OUT, "Request: addr 223, Check Address"),
    r("0000 00DF 0000 00 D43B", IN, "Reply: addr 223, ACK to Check Address"),
    r("0065 0000 0005 01 04 5425", OUT, "Request: addr 101, Get Angle, X and Y axes"),
    r("0000 0065 0005 08 BF4B1C00 41938D00 71C8", IN,
      "Reply: addr 101, Get Angle, X=-0.793396 Y=18.443848",
      fields={"tiltgate_rieker.angle_x": X, "tiltgate_rieker.angle_y": Y}),
    r("0065 0000 000A 05 0100BC614E 1810", OUT,
      "Request: addr 101, Change Lock, level 1 (Unlocked)",
      fields={"tiltgate_rieker.password": "12345678"}),
    r("0000 0065 0000 00 CC1E", IN, "Reply: addr 101, ACK to Change Lock"),
    r("0065 0000 0010 00 3504", OUT, "Request: addr 101, Restart"),
    r("0000 0065 0000 00 CC1E", IN, "Reply: addr 101, ACK to Restart"),
    r("0065 0000 0019 05 01 00000000 995A", OUT,
      "Request: addr 101, Set Zero To Value, X axis (or single axis), offset 0"),
    r("0000 0065 0000 00 CC1E", IN, "Reply: addr 101, ACK to Set Zero To Value"),
    r("0065 0000 001A 01 01 91D4", OUT, "Request: addr 101, Set Zero To Angle, permanent"),
    r("0000 0065 0000 00 CC1E", IN, "Reply: addr 101, ACK to Set Zero To Angle"),
    r("0065 0000 001C 00 3501", OUT, "Request: addr 101, Get Firmware Revision"),
    r("0000 0065 001C 07 52657620412E38 B6C2", IN,
      'Reply: addr 101, Get Firmware Revision, "Rev A.8"'),
    r("0065 0000 001E 00 5500", OUT, "Request: addr 101, Get Lock Level"),
    r("0000 0065 001E 01 01 5EEC", IN, "Reply: addr 101, Get Lock Level, level 1 (Unlocked)"),
    r("0065 0000 0025 00 6513", OUT, "Request: addr 101, Get Serial Number"),
    r("0000 0065 0025 0A 39363232383520202020 DF6D", IN,
      'Reply: addr 101, Get Serial Number, serial "962285"'),
    r("0065 0000 0026 01 08 9BD4", OUT, "Request: addr 101, Set Baud, code 8 (62500 baud)"),
    r("0000 0065 0000 00 CC1E", IN, "Reply: addr 101, ACK to Set Baud"),
    r("0065 0000 0029 01 02 9F64", OUT, "Request: addr 101, Set Filter Response, level 2"),
    r(rieker("0000 0065 0001 01 04"), IN,
      "Reply: addr 101, NAK to Set Filter Response, code 4: Invalid lock level to execute command"),
    # Get Angle of one axis (an H4360): the request's type says which angle the 4 bytes are.
    r(rieker("0065 0000 0005 01 01"), OUT, "Request: addr 101, Get Angle, Single axis"),
    r(rieker("0000 0065 0005 04 BF4B1C00"), IN, "Reply: addr 101, Get Angle, angle=-0.793396",
      fields={"tiltgate_rieker.angle": X}),
    r(rieker("0065 0000 0005 01 03"), OUT, "Request: addr 101, Get Angle, Y axis"),
    r(rieker("0000 0065 0005 04 41938D00"), IN, "Reply: addr 101, Get Angle, Y=18.443848",
      fields={"tiltgate_rieker.angle_y": Y}),
    r(rieker("0065 0000 0021 00"), OUT, "Request: addr 101, Unknown (0x21)"),
    # Bad CRCs: a flipped byte, and the three printed examples docs/protocols.md says are wrong.
    r("0000 0065 0005 08 BF4B1C01 41938D00 71C8", IN,
      "Reply: addr 101, Get Angle, X=-0.79339606 Y=18.443848, bad CRC", status="0"),
    r("0065 0000 000A 05 0100BC614E E414", OUT,
      "Request: addr 101, Change Lock, level 1 (Unlocked), bad CRC", status="0"),
    r("0065 0000 0026 01 08 50CF", OUT,
      "Request: addr 101, Set Baud, code 8 (62500 baud), bad CRC", status="0"),
    r("0000 0065 001C 07 52657620412E38 CC1E", IN,
      'Reply: addr 101, Get Firmware Revision, "Rev A.8", bad CRC', status="0"),
    # Malformed: the manual's ACK with an extra 00 under DL 00, short, truncated.
    r("0000 0065 0000 00 00 CC1E", IN, None, status="0", malformed=True),
    r("0065 00", OUT, "Malformed: 3 bytes, too short for a frame", status=None, malformed=True),
    r("0000 0065 0005 08 BF4B", IN, "Reply: addr 101, Get Angle, truncated", status=None,
      malformed=True),
    # No direction in the flags: guessed from the function and DL.
    r("0065 0000 0005 01 04 5425", NONE, "Request: addr 101, Get Angle, X and Y axes"),
    r("0000 0065 0005 08 BF4B1C00 41938D00 71C8", NONE,
      "Reply: addr 101, Get Angle, X=-0.793396 Y=18.443848"),
    # An ACK answers no Get Angle: it is not paired with the request before it.
    r("0000 0065 0000 00 CC1E", NONE, "Reply: addr 101, ACK"),
]

# docs/protocols.md, "Dyna protocol 2 frame" and "Dyna LRC": the note's examples; the replies
# it does not print are built as spectron/assumptions.h A6 and A7 have them.
DYNA_ASCII = [
    a(":0268006401639C\r\n", OUT, "Request: addr 2, Write EEPROM, location 100 (reserved) = 355"),
    a(":026830\r\n", IN, "Reply: addr 2, Write EEPROM, acknowledged"),
    a(":016633\r\n", OUT, "Request: addr 1, Read Sensor"),
    a(dyna_ascii("016603E9"), IN, "Reply: addr 1, Read Sensor, counts=1001",
      fields={"tiltgate_dyna_ascii.counts": "1001"}),
    a(":146900026A\r\n", OUT, "Request: addr 20, Read EEPROM, location 2 (reserved)"),
    a(dyna_ascii("14690163"), IN, "Reply: addr 20, Read EEPROM, location 2 (reserved) = 355"),
    a(":01680016000F94\r\n", OUT,
      "Request: addr 1, Write EEPROM, location 22 (baud rate code) = 15 (19200 baud)"),
    a(dyna_ascii("0168"), IN, "Reply: addr 1, Write EEPROM, acknowledged"),
    # The note's own print: its LRC holds only if the F went out lowercase.
    a(":01680016000f74\r\n", OUT,
      "Request: addr 1, Write EEPROM, location 22 (baud rate code) = 15 (19200 baud)"),
    a(dyna_ascii("0165"), OUT, "Request: addr 1, Reset"),
    a(dyna_ascii("0165"), IN, "Reply: addr 1, Reset, acknowledged"),
    a(dyna_ascii("0167"), OUT, "Request: addr 1, Read Temperature"),
    a(dyna_ascii("0167FFF6"), IN, "Reply: addr 1, Read Temperature, temperature=-10"),
    a(dyna_ascii("016A"), OUT, "Request: addr 1, Send Revision"),
    a(dyna_ascii("016A0107"), IN, "Reply: addr 1, Send Revision, revision 01.07"),
    a(dyna_ascii("0170"), OUT, "Request: addr 1, Unknown (0x70)"),
    # Bad LRCs: the note's print with an uppercase F, and a flipped character.
    a(":01680016000F74\r\n", OUT,
      "Request: addr 1, Write EEPROM, location 22 (baud rate code) = 15 (19200 baud), bad LRC",
      status="0"),
    a(":016634\r\n", OUT, "Request: addr 1, Read Sensor, bad LRC", status="0"),
    # Malformed.
    a(":0166\r\n", IN, None, status=None, malformed=True),
    a("016633\r\n", IN, None, status=None, malformed=True),
    a(":01GG33\r\n", IN, None, status=None, malformed=True),
    a(":016633", OUT, None, status=None, malformed=True),
    a(b"", IN, "Malformed: empty: \"\"", status=None, malformed=True),
    # No direction in the flags: a read's reply carries a word, its request none.
    a(":016633\r\n", NONE, "Request: addr 1, Read Sensor"),
    a(dyna_ascii("016603E9"), NONE, "Reply: addr 1, Read Sensor, counts=1001"),
]

# docs/protocols.md, "Dyna protocol 1 commands": the note's examples (reset, read the sensor
# and its "1001", write 2501 to location 34), the other commands as A2..A4 have them.
DYNA9 = [
    n(b"\x000\r\n", OUT, "Request: addr 0, Reset Processor"),
    n(b"\r\n", IN, "Reply: addr 0, Reset Processor, acknowledged"),
    n(b"\x00A\r\n", OUT, "Request: addr 0, Read Sensor"),
    n(b"1001\r\n", IN, "Reply: addr 0, Read Sensor, counts=1001",
      fields={"tiltgate_dyna9.counts": "1001"}),
    n(b"\x00E34,2501\r\n", OUT, "Request: addr 0, Write EEPROM, location 34 = 2501"),
    n(b"\r\n", IN, "Reply: addr 0, Write EEPROM, acknowledged"),
    n(b"\x07322\r\n", OUT, "Request: addr 7, Read EEPROM, location 22 (baud rate code)"),
    n(b"15\r\n", IN, "Reply: addr 7, Read EEPROM, location 22 (baud rate code) = 15 (19200 baud)"),
    n(b"\x00C\r\n", OUT, "Request: addr 0, Read Temperature"),
    n(b"-12\r\n", IN, "Reply: addr 0, Read Temperature, temperature=-12"),
    n(b"\x00F\r\n", OUT, "Request: addr 0, Send Firmware Revision"),
    n(b"V2.1\r\n", IN, 'Reply: addr 0, Send Firmware Revision, revision "V2.1"'),
    n(b"\x00Z\r\n", OUT, "Request: addr 0, Unknown (0x5A)"),
    # Malformed: a write without its value, a request and a reply without CR LF, nothing.
    n(b"\x00E34\r\n", OUT, "Request: addr 0, Write EEPROM, malformed", malformed=True),
    n(b"\x00A", OUT, "Request: addr 0, Read Sensor, malformed", malformed=True),
    n(b"10", IN, "Reply: addr 0, Read Sensor, counts=10, malformed", malformed=True),
    n(b"", OUT, "Request: malformed", malformed=True),
    n(b"\x00", OUT, "Request: addr 0, malformed", malformed=True),
    n(b"5\r\n", IN, 'Reply: addr 0, line "5"'),
    # No direction in the flags.
    n(b"\x05A\r\n", NONE, "Request: addr 5, Read Sensor"),
    n(b"1001\r\n", NONE, "Reply: addr 5, Read Sensor, counts=1001"),
]

FIELDS = ["frame.number", "_ws.col.Info", "tiltgate_rieker.crc.status",
          "tiltgate_dyna_ascii.lrc.status", "tiltgate_rieker.angle", "tiltgate_rieker.angle_x",
          "tiltgate_rieker.angle_y", "tiltgate_rieker.password", "tiltgate_dyna_ascii.counts",
          "tiltgate_dyna9.counts"]
MALFORMED = "tiltgate_rieker.malformed || tiltgate_dyna_ascii.malformed || tiltgate_dyna9.malformed"
BAD_CHECK = "tiltgate_rieker.crc.bad || tiltgate_dyna_ascii.lrc.bad"


def tshark(home, *args):
    result = subprocess.run(["tshark", *args, "-X", "lua_script:" + DISSECTOR],
                            capture_output=True, text=True, env=dict(os.environ, HOME=home))
    if result.returncode != 0:
        raise RuntimeError("tshark %s exited %d:\n%s" % (" ".join(args), result.returncode,
                                                         result.stderr))
    # A Lua error while loading the script ("tshark: Lua: syntax error: ...") may not change
    # tshark's exit status.
    if "Lua:" in result.stderr:
        raise RuntimeError("tshark could not load %s:\n%s" % (DISSECTOR, result.stderr))
    return result.stdout


def float32(value):
    return struct.unpack(">f", struct.pack(">f", float(value)))[0]


def info_angles(info):
    """The angles of an Info column "... X=-0.793396 Y=18.443848", by name."""
    return {word.split("=")[0]: float(word.split("=")[1])
            for word in info.replace(",", " ").split() if "=" in word}


def check_frames(home, capture, frames):
    rows = tshark(home, "-r", capture, "-T", "fields", "-E", "occurrence=f",
                  *sum((["-e", f] for f in FIELDS), []))
    seen = {}
    for line in rows.splitlines():
        values = dict(zip(FIELDS, line.split("\t")))
        seen[int(values["frame.number"])] = values
    malformed = set(map(int, tshark(home, "-r", capture, "-Y", MALFORMED, "-T", "fields",
                                    "-e", "frame.number").split()))
    bad_check = set(map(int, tshark(home, "-r", capture, "-Y", BAD_CHECK, "-T", "fields",
                                    "-e", "frame.number").split()))
    for number, frame in enumerate(frames, 1):
        values = seen.get(number, {})
        what = "frame %d (%s %r)" % (number, frame.proto, frame.data)
        if frame.info is not None:
            check("%s: Info is %r" % (what, frame.info), values.get("_ws.col.Info") == frame.info,
                  values.get("_ws.col.Info"))
        if frame.status is not None:
            field = ("tiltgate_rieker.crc.status" if frame.proto == "tiltgate_rieker"
                     else "tiltgate_dyna_ascii.lrc.status")
            check("%s: %s is %s" % (what, field, {"1": "Good", "0": "Bad"}[frame.status]),
                  values.get(field) == frame.status, values.get(field))
            check("%s: %s expert error" % (what, "a" if frame.status == "0" else "no"),
                  (number in bad_check) == (frame.status == "0"), sorted(bad_check))
        check("%s: %smarked malformed" % (what, "" if frame.malformed else "not "),
              (number in malformed) == frame.malformed, sorted(malformed))
        for field, expected in frame.fields.items():
            got = values.get(field, "")
            if isinstance(expected, float):
                # The field prints 6 digits; the Info column the float32's shortest text.
                axis = {"angle": "angle", "angle_x": "X", "angle_y": "Y"}[field.split(".")[1]]
                shown = info_angles(values.get("_ws.col.Info", "")).get(axis)
                check("%s: %s is %r" % (what, field, expected),
                      got != "" and abs(float(got) - expected) < 1e-4 and shown is not None
                      and float32(shown) == expected, "%s, Info %s" % (got, shown))
            else:
                check("%s: %s is %s" % (what, field, expected), got == expected, got)


def prefixes(frames):
    """Every frame cut short at every length, in each direction and none: none may make the
    dissector fail (it would say "Could not decode")."""
    return [Frame(frame.proto, frame.data[:length], direction, None)
            for frame in frames for length in range(len(frame.data))
            for direction in (OUT, IN, NONE)]


def main():
    if shutil.which("tshark") is None:
        print("FAIL: tshark not found: install Debian's tshark package (apt-get install tshark)")
        print("0 passed, 1 failed")
        return 1
    # The test's CRC is the manual's: its check values (docs/protocols.md, "Rieker CRC16").
    for data, crc in [("00", 0x0000), ("FF", 0x4040), ("ABCD", 0xA5BE), ("123456", 0xFB36),
                      ("9876543210", 0xE86E)]:
        check("the test's CRC of %s is %04X" % (data, crc), crc16_arc(bytes.fromhex(data)) == crc)
    check("the test's LRC gives the note's :016633", dyna_ascii("0166") == b":016633\r\n")

    home = tempfile.mkdtemp(prefix="tiltgate-wireshark-")  # no personal preferences or plugins
    try:
        protocols = tshark(home, "-G", "protocols")
        for name in ("tiltgate_rieker", "tiltgate_dyna_ascii", "tiltgate_dyna9"):
            check("the script registers %s" % name, "\t%s\n" % name in protocols)
        frames = RIEKER + DYNA_ASCII + DYNA9
        capture = os.path.join(home, "capture.pcapng")
        write_capture(capture, frames)
        check_frames(home, capture, frames)
        verbose = tshark(home, "-r", capture, "-V")
        check("no Lua error in any packet", "Lua Error" not in verbose,
              [line for line in verbose.splitlines() if "Lua Error" in line][:3])
        check("no Wireshark exception (Malformed Packet) in any packet",
              "[Malformed Packet" not in verbose)
        check("the tree shows the documented X angle", "X angle: -0.793396 degrees" in verbose)
        check("the tree says a bad CRC", "Bad CRC: 0x71C8 received" in verbose)
        check("the tree says a bad LRC", "Bad LRC: 0x74 received, 0x94 computed" in verbose)
        check("a reply links to its request", "Request in frame: 7" in verbose)
        check("  and says how long the sensor took", "Time since request: 0.002000000 seconds"
              in verbose)
        check("an unflagged frame says its direction was guessed",
              "Direction: Reply (1) (guessed)" in verbose)

        cut = os.path.join(home, "cut.pcapng")
        write_capture(cut, prefixes(frames))
        verbose = tshark(home, "-2", "-r", cut, "-V")
        failed = [line.strip() for line in verbose.splitlines()
                  if "Lua Error" in line or "Could not decode" in line]
        check("every frame cut short decodes without a Lua error", not failed, failed[:3])
    except RuntimeError as error:
        check("tshark runs", False, error)
    finally:
        shutil.rmtree(home, ignore_errors=True)
    print("%d passed, %d failed" % (passes, failures))
    return 0 if failures == 0 else 1


if __name__ == "__main__":
    sys.exit(main())
