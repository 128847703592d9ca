"""pcap for Wireshark (``.pcap``): a capture as classic pcap of link type
LINKTYPE_RTAC_SERIAL (250), which Wireshark and tshark dissect as "RTAC Serial".
:class:`PcapWriter` writes one record by record as a recorder goes, :func:`write_pcap` /
:func:`pcap_bytes` a whole capture, and :func:`read_pcap` reads our files and other
recorders' (either byte order, micro- or nanosecond timestamps). What the RTAC link type
has no field for rides in records of ptpcert's own: the start record's payload holds how the
times were taken, the line settings, seat names and notes, and each mark is a
STATUS_CHANGE record that changes no line. Built on the capture's model; the record layout,
and where ptpcert keeps a condition's seat, is specified in ``docs/capture-formats.md``
("pcap for Wireshark").
"""

from __future__ import annotations

import datetime as _dt
import io
import struct
from typing import IO, Iterable

from ptpcert.capture.model import (MODEM_LINES, WITH_DATA, Capture, CaptureError, Chunk, Cond, Mark, capture_time,
                                   checked_line)
from ptpcert.capture.timing import Timing
from ptpcert.model.line import LineSettings

LINKTYPE_RTAC_SERIAL = 250
EPOCH = _dt.datetime(1970, 1, 1, tzinfo=_dt.timezone.utc)
_US = _dt.timedelta(microseconds=1)

#: RTAC serial event types (the link type's definition).
EV_STATUS_CHANGE = 0x00
EV_DATA_TX_START = 0x01
EV_DATA_RX_START = 0x02
EV_DATA_TX_END = 0x03
EV_DATA_RX_END = 0x04
EV_CAPTURE_DATA_LOST = 0x05
EV_CAPTURE_COMPLETE = 0x06
EV_FRAMING_ERROR = 0x07
EV_PARITY_ERROR = 0x08
EV_SERIAL_BREAK = 0x09
EV_SERIAL_OVERFLOW = 0x0A

_COND_EVENT = {Cond.MODEM: EV_STATUS_CHANGE, Cond.LOST: EV_CAPTURE_DATA_LOST, Cond.FRAMING: EV_FRAMING_ERROR,
               Cond.PARITY: EV_PARITY_ERROR, Cond.BREAK: EV_SERIAL_BREAK, Cond.OVERRUN: EV_SERIAL_OVERFLOW}
_EVENT_COND = {v: k for k, v in _COND_EVENT.items()}
#: The footer on condition records: the seat (mirrors the data event types).
_SEAT_FOOTER = {"a": 0x0001, "b": 0x0002}
_FOOTER_SEAT = {v: k for k, v in _SEAT_FOOTER.items()}

PCAP_MAGIC_US = 0xA1B2C3D4
PCAP_MAGIC_NS = 0xA1B23C4D
PCAPNG_MAGIC = 0x0A0D0D0A
SNAPLEN = 65535
RTAC_HEADER = struct.Struct(">IIBBH")
MAX_PAYLOAD = SNAPLEN - RTAC_HEADER.size
_GLOBAL = struct.Struct("<IHHiIII")
_RECORD = struct.Struct("<IIII")


def _lines_byte(lines: Iterable[str] | None) -> int:
    return sum(1 << MODEM_LINES.index(x) for x in (lines or ()))


def _byte_lines(v: int) -> frozenset[str]:
    return frozenset(name for i, name in enumerate(MODEM_LINES) if v >> i & 1)


def _start_us(start: _dt.datetime | None) -> int:
    return 0 if start is None else (start - EPOCH) // _US


#: The start record's payload, when the capture says more than its chunks: this first line,
#: then ``key: value`` lines as in the hex log's header (``timing``, ``line``, ``a``, ``b``,
#: ``note``), UTF-8.
START_TAG = b"ptpcert-capture 1"
#: A mark's record: a STATUS_CHANGE that changes no line, its payload this line and the text.
MARK_TAG = b"ptpcert-mark"


def _start_payload(cap: Capture | None, timing: Timing | None) -> bytes:
    lines = [] if timing is None else [f"timing: {timing.text()}"]
    if cap is not None:
        if cap.line is not None:
            lines.append(f"line: {cap.line}")
        if cap.seats != {"a": "a", "b": "b"}:
            lines += [f"{s}: {cap.seats[s]}" for s in ("a", "b")]
        lines += [f"note: {n}" for n in cap.notes]
    if not lines:
        return b""
    return START_TAG + b"\n" + "\n".join(lines).encode("utf-8") + b"\n"


def _read_start_payload(payload: bytes, head: dict) -> None:
    """The capture's header from our start record's payload into ``head`` (keys of a later
    version are ignored)."""
    for raw in payload.decode("utf-8", "replace").splitlines()[1:]:
        key, sep, value = raw.partition(":")
        key, value = key.strip().lower(), value.strip()
        if not sep:
            continue
        if key == "timing":
            head["timing"] = Timing.parse(value)
        elif key == "line":
            try:
                head["line"] = checked_line(LineSettings.parse(value))
            except ValueError as exc:
                raise CaptureError(str(exc)) from None
        elif key in ("a", "b") and value:
            head["seats"][key] = value
        elif key == "note":
            head["notes"].append(value)


class PcapWriter:
    """Writes a pcap file record by record (for a recorder that writes as it goes): the
    global header and the start record at once (saying how the times are taken, when
    ``timing`` is given, and the line settings, seat names and notes of ``head``), then one
    or more records per chunk and one per mark."""

    def __init__(self, fp: IO[bytes], start: _dt.datetime | None = None, timing: Timing | None = None,
                 head: Capture | None = None):
        self.fp = fp
        self.base = _start_us(start)
        if self.base < 0:
            raise CaptureError("pcap cannot hold times before 1970")
        self.lines_a = 0
        fp.write(_GLOBAL.pack(PCAP_MAGIC_US, 2, 4, 0, 0, SNAPLEN, LINKTYPE_RTAC_SERIAL))
        self._record(0.0, EV_STATUS_CHANGE, 0, _SEAT_FOOTER["a"], _start_payload(head, timing))

    def _record(self, t: float, event: int, ctrl: int, footer: int, payload: bytes) -> None:
        us = self.base + round(capture_time(t) * 1_000_000)
        sec, usec = divmod(us, 1_000_000)
        if sec > 0xFFFFFFFF:
            raise CaptureError("pcap cannot hold times after 2106")
        body = RTAC_HEADER.pack(sec, usec, event, ctrl, footer) + payload
        self.fp.write(_RECORD.pack(sec, usec, len(body), len(body)) + body)

    def chunk(self, c: Chunk) -> None:
        if c.condition is None:
            event = EV_DATA_TX_START if c.seat == "a" else EV_DATA_RX_START
            for i in range(0, len(c.data), MAX_PAYLOAD):
                self._record(c.t, event, self.lines_a, 0, c.data[i:i + MAX_PAYLOAD])
            return
        footer = _SEAT_FOOTER[c.seat]
        ctrl = self.lines_a
        payload = b""
        if c.condition is Cond.MODEM:
            ctrl = _lines_byte(c.lines)
            if c.seat == "a":
                self.lines_a = ctrl
        elif c.condition is Cond.BREAK and c.duration is not None:
            payload = struct.pack(">I", min(round(c.duration * 1_000_000), 0xFFFFFFFF))
        elif c.condition in WITH_DATA:
            payload = c.data
        for i in range(0, max(len(payload), 1), MAX_PAYLOAD):
            self._record(c.t, _COND_EVENT[c.condition], ctrl, footer, payload[i:i + MAX_PAYLOAD])

    def mark(self, m: Mark) -> None:
        self._record(m.t, EV_STATUS_CHANGE, self.lines_a, 0, MARK_TAG + b"\n" + m.text.encode("utf-8"))

    def close(self, end: float | None = None) -> None:
        if end is not None:
            self._record(end, EV_CAPTURE_COMPLETE, self.lines_a, 0, b"")
        self.fp.flush()


def write_pcap(cap: Capture, fp: IO[bytes]) -> None:
    """Write the whole capture as a pcap file."""
    w = PcapWriter(fp, cap.start, cap.timing, cap)
    items = [(m.t, 0, m) for m in cap.marks] + [(c.t, 1, c) for c in cap.chunks]
    items.sort(key=lambda x: (x[0], x[1]))     # a mark before a chunk at the same time
    for _, _, x in items:
        (w.mark if isinstance(x, Mark) else w.chunk)(x)
    w.close(cap.end)


def pcap_bytes(cap: Capture) -> bytes:
    """The capture as the bytes of a pcap file."""
    buf = io.BytesIO()
    write_pcap(cap, buf)
    return buf.getvalue()


def read_pcap(data: bytes, source: str = "") -> Capture:
    """A capture from a pcap file of link type LINKTYPE_RTAC_SERIAL (docs/capture-formats.md,
    "pcap for Wireshark"). Errors name the record number (1 = the first record)."""
    if len(data) < 24:
        raise CaptureError(f"too short for a pcap file ({len(data)} bytes; the file header alone is 24)", source)
    (magic_le,) = struct.unpack_from("<I", data)
    if magic_le == PCAPNG_MAGIC:
        raise CaptureError("this is pcapng; ptpcert reads classic pcap (in Wireshark: File > Save As, "
                           "format 'Wireshark/tcpdump/... - pcap')", source)
    order = ""
    for o in ("<", ">"):
        (m,) = struct.unpack_from(o + "I", data)
        if m in (PCAP_MAGIC_US, PCAP_MAGIC_NS):
            order, nano = o, m == PCAP_MAGIC_NS
    if not order:
        raise CaptureError(f"not a pcap file (magic number {data[:4].hex()})", source)
    _, major, minor, _, _, _, network = struct.unpack_from(order + "IHHiIII", data)
    if major != 2:
        raise CaptureError(f"pcap version {major}.{minor} is not 2.x", source)
    if network & 0xFFFF != LINKTYPE_RTAC_SERIAL:
        raise CaptureError(f"link type {network & 0xFFFF} is not LINKTYPE_RTAC_SERIAL ({LINKTYPE_RTAC_SERIAL}); "
                           "ptpcert reads serial-line captures of that link type only", source)
    rec = struct.Struct(order + "IIII")
    pos, n = 24, 0
    records: list[tuple[int, int, int, int, int, bytes]] = []
    chunks: list[Chunk] = []
    notes: list[str] = []
    end: float | None = None
    head: dict = {"timing": None, "line": None, "seats": {"a": "a", "b": "b"}, "notes": []}
    marks: list[Mark] = []
    lines_a = 0
    while pos < len(data):
        n += 1
        if pos + rec.size > len(data):
            raise CaptureError(f"the file ends inside the header of record {n}", source)
        sec, frac, incl, orig = rec.unpack_from(data, pos)
        pos += rec.size
        if pos + incl > len(data):
            raise CaptureError(f"record {n} says {incl} bytes, but only {len(data) - pos} remain "
                               "(the file is cut short)", source)
        body = data[pos:pos + incl]
        pos += incl
        if incl < orig:
            raise CaptureError(f"record {n} was cut to {incl} of {orig} bytes when captured (snapshot length)",
                               source)
        if incl < RTAC_HEADER.size:
            raise CaptureError(f"record {n} has {incl} bytes, fewer than the 12-byte RTAC serial header", source)
        us = sec * 1_000_000 + (round(frac / 1000) if nano else frac)
        _, _, event, ctrl, footer = RTAC_HEADER.unpack_from(body)
        records.append((n, us, event, ctrl, footer, body[RTAC_HEADER.size:]))
    # t = 0 is the earliest record (the first one, unless another recorder wrote them out of order)
    first_us = min((r[1] for r in records), default=None)
    for n, us, event, ctrl, footer, payload in records:
        t = (us - first_us) / 1_000_000
        try:
            if n == 1 and event == EV_STATUS_CHANGE and ctrl == 0 and not payload:
                continue     # the start record (ours, or a recorder's with nothing asserted)
            if n == 1 and event == EV_STATUS_CHANGE and ctrl == 0 and payload.startswith(START_TAG):
                _read_start_payload(payload, head)       # ours, with the capture's header
                continue
            if event == EV_STATUS_CHANGE and payload.startswith(MARK_TAG + b"\n"):
                marks.append(Mark(t, payload[len(MARK_TAG) + 1:].decode("utf-8", "replace")))
                continue
            if event in (EV_DATA_TX_START, EV_DATA_TX_END, EV_DATA_RX_START, EV_DATA_RX_END):
                if ctrl != lines_a:   # another recorder's lines changed on a data record
                    chunks.append(Chunk(t, "a", condition=Cond.MODEM, lines=_byte_lines(ctrl)))
                    lines_a = ctrl
                if payload:
                    seat = "a" if event in (EV_DATA_TX_START, EV_DATA_TX_END) else "b"
                    chunks.append(Chunk(t, seat, payload))
            elif event == EV_CAPTURE_COMPLETE:
                end = t
            elif event in _EVENT_COND:
                cond = _EVENT_COND[event]
                default = "a" if cond is Cond.MODEM else "b"
                seat = _FOOTER_SEAT.get(footer, default)
                if cond is Cond.MODEM:
                    chunks.append(Chunk(t, seat, condition=cond, lines=_byte_lines(ctrl)))
                    if seat == "a":
                        lines_a = ctrl
                elif cond is Cond.BREAK:
                    dur = None
                    if len(payload) == 4:
                        dur = struct.unpack(">I", payload)[0] / 1_000_000
                    elif payload:
                        notes.append(f"record {n}: a BREAK with {len(payload)} payload bytes; duration not read")
                    chunks.append(Chunk(t, seat, condition=cond, duration=dur))
                elif cond in WITH_DATA:
                    chunks.append(Chunk(t, seat, payload, cond))
                else:
                    chunks.append(Chunk(t, seat, condition=cond))
            else:
                notes.append(f"record {n}: event type 0x{event:02X} is unknown; skipped")
        except CaptureError as exc:
            raise CaptureError(f"record {n}: {exc.message}", source) from None
    start = None if not first_us else EPOCH + _dt.timedelta(microseconds=first_us)
    if end is not None and chunks and end < max(c.t for c in chunks):
        notes.append(f"CAPTURE_COMPLETE at {end:.6f} s comes before the last chunk; ignored")
        end = None
    return Capture(chunks, head["seats"], head["line"], start, end, head["notes"] + notes, marks, head["timing"])

