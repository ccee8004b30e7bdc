"""The store's files read by their documented layout (store/record_frame.h, docs/northbound.md
"The store"), without the gateway's code: segment files NNNNNNNNNNNNNNNNNNNN.seg, an 8-byte
header then frames of u32 length, u32 CRC-32 (of the length's bytes and the body), body: u8
format, u8 qos, u16 topic length, i64 time (Unix ms), topic, payload; all little-endian. The
`cursor` file: 8-byte magic, u64 segment id, u64 offset, u32 CRC-32."""
import glob
import os
import struct
import zlib

SEGMENT_HEADER = 8
FRAME_HEADER = 8


class Frame:
    def __init__(self, segment, offset, size, time_ms, topic, payload):
        self.segment = segment  # path
        self.offset = offset
        self.size = size
        self.time_ms = time_ms
        self.topic = topic
        self.payload = payload


def segments(state_dir):
    """Every segment file under state_dir (wherever the gateway keeps its store), oldest
    first."""
    found = glob.glob(os.path.join(state_dir, "**", "*.seg"), recursive=True)
    return sorted(found, key=os.path.basename)


def frames(path):
    """The whole, valid frames of one segment, in order, up to the first that is not."""
    with open(path, "rb") as f:
        data = f.read()
    out = []
    at = SEGMENT_HEADER
    while at + FRAME_HEADER <= len(data):
        length, crc = struct.unpack_from("<II", data, at)
        end = at + FRAME_HEADER + length
        if end > len(data) or zlib.crc32(data[at:at + 4] + data[at + 8:end]) != crc:
            break
        _, _, topic_length, time_ms = struct.unpack_from("<BBHq", data, at + 8)
        body = data[at + 8 + 12:end]
        out.append(Frame(path, at, end - at, time_ms, body[:topic_length].decode(),
                         body[topic_length:]))
        at = end
    return out


def cursor(state_dir):
    """(segment id, offset) the replay has reached, or None without a cursor file."""
    found = glob.glob(os.path.join(state_dir, "**", "cursor"), recursive=True)
    if not found:
        return None
    with open(found[0], "rb") as f:
        data = f.read()
    if len(data) != 28:
        return None
    return struct.unpack_from("<QQ", data, 8)


def pending(state_dir):
    """The frames not yet replayed: those at or after the cursor."""
    position = cursor(state_dir)
    out = []
    for path in segments(state_dir):
        segment_id = int(os.path.basename(path)[:-4])
        for frame in frames(path):
            if position is None or (segment_id, frame.offset) >= position:
                out.append(frame)
    return out
