"""lcmlog: reads an lcm-logger file event by event.

The format (LCM's eventlog): each event is a sync word 0xEDA1DA01, the
event number (int64), the log time in microseconds (int64), the channel
name's length and the data's length (int32 each), then the name and the
data, all big-endian. A reader of our own rather than lcm.EventLog so that
a damaged file is reported with where and how it is damaged, after the
events before the damage have been handed out.
"""
import struct

SYNC = 0xEDA1DA01
HEADER = struct.Struct(">IqqII")
MAX_CHANNEL = 256          # LCM's own limit on a channel name
MAX_DATA = 256 * 1024 * 1024


class LogError(Exception):
    """The log is damaged at byte `offset`; events before it were read."""

    def __init__(self, offset, what):
        super().__init__(f"byte {offset}: {what}")
        self.offset = offset


def events(f):
    """Yields (event number, log time us, channel, data); raises LogError
    at the first damaged event."""
    offset = 0
    while True:
        head = f.read(HEADER.size)
        if not head:
            return
        if len(head) < HEADER.size:
            raise LogError(offset, f"truncated event header ({len(head)} of {HEADER.size} bytes)")
        sync, num, utime, clen, dlen = HEADER.unpack(head)
        if sync != SYNC:
            raise LogError(offset, f"no event here (sync word 0x{sync:08X}, expected 0x{SYNC:08X}): not an lcm-logger file, or damaged")
        if clen == 0 or clen > MAX_CHANNEL or dlen > MAX_DATA:
            raise LogError(offset, f"implausible event (channel name {clen} bytes, data {dlen} bytes)")
        body = f.read(clen + dlen)
        if len(body) < clen + dlen:
            raise LogError(offset, f"truncated event {num} ({len(body)} of {clen + dlen} bytes after its header)")
        try:
            channel = body[:clen].decode("ascii")
        except UnicodeDecodeError:
            raise LogError(offset, "channel name is not ASCII") from None
        yield num, utime, channel, body[clen:]
        offset += HEADER.size + clen + dlen
