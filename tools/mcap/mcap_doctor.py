#!/usr/bin/env python3
"""mcap_doctor: checks an MCAP file's structure, as `mcap doctor` does.

For where the Go `mcap` CLI cannot be installed: the same checks on the
records as the mcap package (PyPI) reads them, record by record at their
byte offsets. Errors: bad magic; a record that does not parse; schema id 0;
two schema or channel records with one id that differ; a channel of an
unknown schema; a message of an unknown channel; a chunk whose data does
not decompress to its uncompressed_size, fails its CRC, holds other than
schema, channel and message records, or whose message_start/end_time are
not its messages' earliest and latest log times; a chunk index that does
not point at a chunk of the same length, times, compression and sizes, or
two for one chunk; an indexed chunk whose channels or schemas are not
repeated in the summary section; a summary schema or channel absent from
the data section; the data section's CRC (DataEnd) or the summary's CRC
(Footer) wrong; a footer whose summary_start is not where the summary
begins; no DataEnd or Footer; more than one Statistics record, or one whose
message, schema, channel or chunk counts, per-channel counts or start and
end times differ from the file's. Warnings: an empty Header.library, an
unknown profile, duplicate records in the data section, log times that go
back (lcm-logger's receive times may).
    mcap_doctor.py FILE.mcap      exit 0: no errors; 1: errors (listed)
"""
import io
import struct
import sys
import zlib

from mcap.data_stream import ReadDataStream
from mcap.opcode import Opcode
from mcap.records import (AttachmentIndex, Channel, Chunk, ChunkIndex, DataEnd, Footer, Header, Message,
                          MessageIndex, Metadata, MetadataIndex, Schema, Statistics, SummaryOffset, Attachment)

MAGIC = b"\x89MCAP0\r\n"
RECORD_HEADER = 9                     # opcode (1) + length (8)
READERS = {
    Opcode.HEADER: Header.read, Opcode.FOOTER: Footer.read, Opcode.SCHEMA: Schema.read,
    Opcode.CHANNEL: Channel.read, Opcode.MESSAGE: Message.read, Opcode.CHUNK: Chunk.read,
    Opcode.MESSAGE_INDEX: MessageIndex.read, Opcode.CHUNK_INDEX: ChunkIndex.read, Opcode.ATTACHMENT: Attachment.read,
    Opcode.ATTACHMENT_INDEX: AttachmentIndex.read, Opcode.STATISTICS: Statistics.read,
    Opcode.METADATA: Metadata.read, Opcode.METADATA_INDEX: MetadataIndex.read,
    Opcode.SUMMARY_OFFSET: SummaryOffset.read, Opcode.DATA_END: DataEnd.read,
}


def records(buf, start, end):
    """(offset, opcode, record or None, error) of every record in buf[start:end]."""
    off = start
    while off < end:
        if off + RECORD_HEADER > end:
            yield off, None, None, f"a record header cut short at byte {off}"
            return
        opcode, length = struct.unpack_from("<BQ", buf, off)
        body = off + RECORD_HEADER
        if body + length > end:
            yield off, opcode, None, f"record at byte {off} (opcode {opcode:#x}) runs past the end ({length} bytes)"
            return
        rec, err = None, None
        reader = READERS.get(opcode)
        if reader is not None:
            s = ReadDataStream(io.BytesIO(buf[body:body + length]))
            try:
                rec = reader(s, length) if opcode == Opcode.MESSAGE else reader(s)
            except Exception as e:     # noqa: BLE001  any parse failure is a finding
                err = f"record at byte {off} (opcode {opcode:#x}) does not parse: {e}"
        yield off, opcode, rec, err
        off = body + length


class Doctor:
    def __init__(self, buf):
        self.buf = buf
        self.errors, self.warnings = [], []
        self.schemas, self.channels = {}, {}           # id -> record, data section
        self.summary_schemas, self.summary_channels = set(), set()
        self.chunks = {}                               # offset -> (record length, Chunk, channel ids)
        self.chunk_indexes = {}
        self.statistics = None
        self.count, self.per_channel = 0, {}
        self.t_min, self.t_max, self.t_last = None, None, None
        self.n_chunks = 0

    def error(self, text):
        self.errors.append(text)

    def warn(self, text):
        self.warnings.append(text)

    # ---- the records ------------------------------------------------------------
    def define(self, what, table, in_summary_ids, rec, in_summary, fields):
        """A schema or channel record: one id, one definition; the summary
        section repeats only what the data section defines."""
        prev = table.get(rec.id)
        if prev is not None and any(getattr(prev, f) != getattr(rec, f) for f in fields):
            self.error(f"two {what} records with id {rec.id} differ")
        if in_summary:
            if prev is None:
                self.error(f"{what} {rec.id} of the summary section is not in the data section")
            in_summary_ids.add(rec.id)
        else:
            if prev is not None:
                self.warn(f"duplicate {what} records in the data section with id {rec.id}")
            table[rec.id] = rec

    def schema(self, s, in_summary):
        if s.id == 0:
            self.error("Schema.id 0 is reserved")
        self.define("schema", self.schemas, self.summary_schemas, s, in_summary, ("name", "encoding", "data"))

    def channel(self, c, in_summary):
        self.define("channel", self.channels, self.summary_channels, c, in_summary,
                    ("schema_id", "topic", "message_encoding", "metadata"))
        if c.schema_id != 0 and c.schema_id not in self.schemas:
            self.error(f"channel {c.id} ({c.topic}) of unknown schema {c.schema_id}")

    def content(self, opcode, rec, in_summary):
        """A schema, channel or message record, in a chunk or not; False for any other."""
        if opcode == Opcode.SCHEMA:
            self.schema(rec, in_summary)
        elif opcode == Opcode.CHANNEL:
            self.channel(rec, in_summary)
        elif opcode == Opcode.MESSAGE:
            self.message(rec)
        else:
            return False
        return True

    def message(self, m):
        ch = self.channels.get(m.channel_id)
        if ch is None:
            self.error(f"a message of channel {m.channel_id} before that channel's record")
        if self.t_last is not None and m.log_time < self.t_last:
            self.warn_back = getattr(self, "warn_back", 0) + 1
        self.t_last = m.log_time if self.t_last is None else max(self.t_last, m.log_time)
        self.t_min = m.log_time if self.t_min is None else min(self.t_min, m.log_time)
        self.t_max = m.log_time if self.t_max is None else max(self.t_max, m.log_time)
        self.count += 1
        self.per_channel[m.channel_id] = self.per_channel.get(m.channel_id, 0) + 1

    def chunk(self, off, length, c):
        self.n_chunks += 1
        try:
            if c.compression == "zstd":
                import zstandard
                data = zstandard.ZstdDecompressor().decompress(c.data, max_output_size=c.uncompressed_size)
            elif c.compression == "lz4":
                import lz4.frame
                data = lz4.frame.decompress(c.data)
            elif c.compression == "":
                data = c.data
            else:
                self.error(f"chunk at byte {off}: unknown compression {c.compression!r}")
                return
        except Exception as e:     # noqa: BLE001
            self.error(f"chunk at byte {off} does not decompress: {e}")
            return
        if len(data) != c.uncompressed_size:
            self.error(f"chunk at byte {off}: {len(data)} bytes uncompressed, uncompressed_size {c.uncompressed_size}")
            return
        if c.uncompressed_crc != 0 and zlib.crc32(data) != c.uncompressed_crc:
            self.error(f"chunk at byte {off}: CRC {zlib.crc32(data):#x} != {c.uncompressed_crc:#x}")
            return
        t0, t1, ids = None, None, set()
        for roff, opcode, rec, err in records(data, 0, len(data)):
            if err:
                self.error(f"chunk at byte {off}: {err}")
                return
            if not self.content(opcode, rec, False):
                self.error(f"chunk at byte {off}: a record of opcode {opcode:#x} inside it")
            elif opcode == Opcode.MESSAGE:
                ids.add(rec.channel_id)
                t0 = rec.log_time if t0 is None else min(t0, rec.log_time)
                t1 = rec.log_time if t1 is None else max(t1, rec.log_time)
        if t0 is not None and (t0, t1) != (c.message_start_time, c.message_end_time):
            self.error(f"chunk at byte {off}: message times {c.message_start_time}..{c.message_end_time}, "
                       f"its messages' {t0}..{t1}")
        self.chunks[off] = (length, c, ids)

    # ---- the file ----------------------------------------------------------------
    def examine(self):
        buf = self.buf
        if len(buf) < 2 * len(MAGIC) or buf[:8] != MAGIC:
            self.error("no MCAP magic at the start")
            return self
        if buf[-8:] != MAGIC:
            self.error("no MCAP magic at the end (cut short?)")
        in_summary, data_end, footer, footer_off, first_summary = False, None, None, None, None
        for off, opcode, rec, err in records(buf, 8, len(buf) - 8 if buf[-8:] == MAGIC else len(buf)):
            if err:
                self.error(err)
                break
            if in_summary and first_summary is None and opcode != Opcode.FOOTER:
                first_summary = off
            if opcode == Opcode.HEADER:
                if not rec.library:
                    self.warn("Header.library is empty")
                if rec.profile not in ("", "ros1", "ros2"):
                    self.warn(f"Header.profile {rec.profile!r} is not a well-known profile")
            elif self.content(opcode, rec, in_summary):
                pass
            elif opcode == Opcode.CHUNK:
                length = struct.unpack_from("<Q", buf, off + 1)[0] + RECORD_HEADER
                self.chunk(off, length, rec)
            elif opcode == Opcode.CHUNK_INDEX:
                if rec.chunk_start_offset in self.chunk_indexes:
                    self.error(f"two chunk indexes for the chunk at byte {rec.chunk_start_offset}")
                self.chunk_indexes[rec.chunk_start_offset] = rec
            elif opcode == Opcode.STATISTICS:
                if self.statistics is not None:
                    self.error("more than one Statistics record")
                self.statistics = rec
            elif opcode == Opcode.DATA_END:
                data_end, in_summary = rec, True
                if rec.data_section_crc != 0 and zlib.crc32(buf[:off]) != rec.data_section_crc:
                    self.error(f"data section CRC {zlib.crc32(buf[:off]):#x} != DataEnd's {rec.data_section_crc:#x}")
            elif opcode == Opcode.FOOTER:
                footer, footer_off = rec, off
        if data_end is None:
            self.error("no DataEnd record")
        if footer is None:
            self.error("no Footer record")
        else:
            self.check_footer(footer, footer_off, first_summary)
        self.check_chunk_indexes()
        self.check_statistics()
        back = getattr(self, "warn_back", 0)
        if back:
            self.warn(f"{back} messages have a log time before an earlier message's")
        return self

    def check_footer(self, f, off, first_summary):
        if f.summary_start != (first_summary or 0):
            self.error(f"Footer.summary_start {f.summary_start}, the summary section begins at {first_summary or 0}")
        if f.summary_crc != 0:
            start = f.summary_start or off
            crc = zlib.crc32(self.buf[start:off + RECORD_HEADER + 16])
            if crc != f.summary_crc:
                self.error(f"summary CRC {crc:#x} != Footer's {f.summary_crc:#x}")

    def check_chunk_indexes(self):
        for off, ci in self.chunk_indexes.items():
            if off not in self.chunks:
                self.error(f"a chunk index points at byte {off}, where no chunk begins")
                continue
            length, c, ids = self.chunks[off]
            want = (length, c.message_start_time, c.message_end_time, c.compression, len(c.data), c.uncompressed_size)
            got = (ci.chunk_length, ci.message_start_time, ci.message_end_time, ci.compression, ci.compressed_size,
                   ci.uncompressed_size)
            if want != got:
                self.error(f"the chunk index of the chunk at byte {off} says {got}, the chunk {want}")
            for cid in ids:
                if cid not in self.summary_channels:
                    self.error(f"indexed chunk at byte {off}: channel {cid} is not repeated in the summary")
                sid = self.channels[cid].schema_id if cid in self.channels else 0
                if sid and sid not in self.summary_schemas:
                    self.error(f"indexed chunk at byte {off}: schema {sid} is not repeated in the summary")

    def check_statistics(self):
        s = self.statistics
        if s is None:
            return
        if s.message_count != self.count:
            self.error(f"Statistics.message_count {s.message_count}, the file has {self.count} messages")
        if self.count and (s.message_start_time, s.message_end_time) != (self.t_min, self.t_max):
            self.error(f"Statistics times {s.message_start_time}..{s.message_end_time}, "
                       f"the messages' {self.t_min}..{self.t_max}")
        for what, mine, theirs in (("schema", len(self.schemas), s.schema_count),
                                   ("channel", len(self.channels), s.channel_count),
                                   ("chunk", self.n_chunks, s.chunk_count)):
            if mine != theirs:
                self.error(f"Statistics.{what}_count {theirs}, the file has {mine}")
        per = {k: v for k, v in s.channel_message_counts.items() if v}
        if per != self.per_channel:
            self.error("Statistics.channel_message_counts differ from the messages per channel")


def examine(buf):
    return Doctor(buf).examine()


def main(path):
    with open(path, "rb") as f:
        d = examine(f.read())
    for w in d.warnings:
        print(f"mcap_doctor: warning: {w}")
    for e in d.errors:
        print(f"mcap_doctor: ERROR: {e}")
    print(f"mcap_doctor: {path}: {d.count} messages on {len(d.channels)} channels in {d.n_chunks} chunks; "
          f"{len(d.errors)} errors, {len(d.warnings)} warnings")
    return 1 if d.errors else 0


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__.rsplit("\n", 2)[-2])
    sys.exit(main(sys.argv[1]))
