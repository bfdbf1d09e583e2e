#!/usr/bin/env python3
"""decode_check: decodes every event of an lcm-logger file with the
lcm-gen Python types, as the viewer's bridge does (tools/viewer/events.py:
TYPE.decode(data)), re-encodes it and checks the bytes are the event's own,
followed by nothing or by one authentication trailer (src/daemons/common/auth.h).
Prints the events decoded per type; exit 1 if any event fails.
    decode_check.py PYTHON_TYPES_DIR LOG     (lcm-gen -p --ppath PYTHON_TYPES_DIR)
"""
import importlib
import os
import struct
import sys

FIXED_BYTES, TAG_BYTES = 40, 21  # auth.h: the trailer's fixed part; one tag per receiver before it
SYNC = 0xEDA1DA01


def load_types(root):
    sys.path.insert(0, root)
    types = {}
    for f in sorted(os.listdir(os.path.join(root, "tandem"))):
        if f.endswith(".py") and f != "__init__.py":
            mod = importlib.import_module("tandem." + f[:-3])
            cls = getattr(mod, f[:-3])
            types[cls._get_packed_fingerprint()] = cls
    return types


def events(path):
    with open(path, "rb") as f:
        while True:
            head = f.read(28)
            if len(head) < 28:
                return
            sync, _num, _t, ch_len, data_len = struct.unpack(">IqqII", head)
            if sync != SYNC:
                raise ValueError("not an LCM log")
            channel = f.read(ch_len).decode()
            yield channel, f.read(data_len)


def is_trailer(data, rest):
    """True when data ends in exactly rest bytes of one v2 trailer."""
    if rest < FIXED_BYTES:
        return False
    f = data[len(data) - FIXED_BYTES:]
    return (f[0:3] == b"TA\x02" and f[39] == 0 and rest == FIXED_BYTES + f[38] * TAG_BYTES)


def main():
    types = load_types(sys.argv[1])
    decoded, bad, n, signed = {}, 0, 0, 0
    for channel, data in events(sys.argv[2]):
        if channel == "LCM_SELF_TEST":
            continue  # LCM's own start-up probe, not a tandem message
        n += 1
        try:
            cls = types[data[:8]]
            enc = cls.decode(data).encode()
            rest = len(data) - len(enc)
            if (rest != 0 and not is_trailer(data, rest)) or data[:len(enc)] != enc:
                raise ValueError("re-encoding gives other bytes (%d left)" % rest)
            signed += rest != 0
            decoded[cls.__name__] = decoded.get(cls.__name__, 0) + 1
        except Exception as e:  # any failure of any event is reported
            bad += 1
            if bad <= 10:
                print("python decode FAILED: %s: %r" % (channel, e))
    print("python decoding: %d events, %d with a trailer, %d types, failed %d: %s"
          % (n, signed, len(decoded), bad, dict(sorted(decoded.items()))))
    return 0 if bad == 0 and n > 0 else 1


if __name__ == "__main__":
    sys.exit(main())
