"""A case's transcript as it is kept: the bytes on the line packed into runs (results schema
2: one entry per burst of one side, its bytes in base64), unpacked again for tools that read
byte by byte, and read back as the bytes, character errors and BREAKs in time order that the
views and the root-cause signatures walk through.

Part of :mod:`ptpcert.results`; standard library only.
"""

from __future__ import annotations

import base64
from typing import Any, Iterable

#: Entries of the bytes on the line: one per byte (the runner's log, and schema 1) and
#: their runs (schema 2).
BYTE_KINDS = {"byte": "bytes", "char_error": "char_errors"}
RUN_KINDS = {run: one for one, run in BYTE_KINDS.items()}


def pack_transcript(log: Iterable[dict[str, Any]]) -> list[dict[str, Any]]:
    """A transcript with one entry per byte as runs: consecutive bytes of one side, kind
    and step become one entry ``{"t", "dir", "kind": "bytes" | "char_errors", "step",
    "base64": "AhA=", "times": [...]}`` (the bytes in base64, RFC 4648: a flood's 20000
    bytes take 27 kB, not 40 kB as hex), ``times`` only where the bytes' times differ from
    ``t``. Every other entry (BREAK, windows, marks) is kept as it is."""
    out: list[dict[str, Any]] = []
    cur: dict[str, Any] | None = None
    data = bytearray()
    times: list[float] = []

    def flush() -> None:
        nonlocal cur
        if cur is not None:
            cur["base64"] = base64.b64encode(bytes(data)).decode("ascii")
            if any(t != times[0] for t in times):
                cur["times"] = list(times)
            out.append(cur)
            cur = None

    for e in log:
        kind = e.get("kind")
        if kind in BYTE_KINDS:
            run = BYTE_KINDS[kind]
            d, step = e.get("dir", "tester"), e.get("step", 0)
            if cur is None or cur["kind"] != run or cur["dir"] != d or cur["step"] != step:
                flush()
                cur = {"t": e["t"], "dir": d, "kind": run, "step": step}
                data, times = bytearray(), []
            data.append(int(e["byte"]) & 0xFF)
            times.append(e["t"])
        else:
            flush()
            out.append(dict(e))
    flush()
    return out


def unpack_transcript(transcript: Iterable[dict[str, Any]]) -> list[dict[str, Any]]:
    """Inverse of :func:`pack_transcript`: one entry per byte again (entries of schema 1
    pass unchanged), for tools that read a transcript byte by byte."""
    out: list[dict[str, Any]] = []
    for e in transcript:
        kind = e.get("kind")
        if kind not in RUN_KINDS:
            out.append(e)
            continue
        one, data = RUN_KINDS[kind], run_bytes(e)
        times = e.get("times") or [e["t"]] * len(data)
        base = {k: v for k, v in e.items() if k not in ("kind", "base64", "times", "t")}
        out.extend({**base, "t": times[i], "kind": one, "byte": b} for i, b in enumerate(data))
    return out


def run_bytes(e: dict[str, Any]) -> bytes:
    """The bytes of a run entry."""
    text = e.get("base64")
    if not isinstance(text, str):
        raise TypeError("base64 missing")
    return base64.b64decode(text, validate=True)


def wire_runs(transcript: Iterable[dict[str, Any]]) -> list[tuple[float, str, str, Any, int]]:
    """The bytes, character errors and BREAKs of a transcript (runs, or one entry per byte)
    as ``(t, dir, kind, value, step)`` in time order (equal times keep the log's order):
    ``kind`` "byte" or "char_error" with ``value`` the bytes that arrived together at ``t``
    (a run whose bytes share one time stays whole), or "break" with its duration."""
    out: list[tuple[float, str, str, Any, int]] = []
    for e in transcript:
        kind = e.get("kind")
        if kind in RUN_KINDS:
            one, d, step = RUN_KINDS[kind], e.get("dir", "tester"), int(e.get("step", 0))
            data = run_bytes(e)
            times = e.get("times")
            if times:
                out.extend((float(x), d, one, data[i:i + 1], step) for i, x in enumerate(times))
            elif data:
                out.append((float(e["t"]), d, one, data, step))
        elif kind in BYTE_KINDS and "t" in e:
            out.append((float(e["t"]), e.get("dir", "tester"), kind, bytes([int(e.get("byte", 0)) & 0xFF]),
                        int(e.get("step", 0))))
        elif kind == "break" and "t" in e:
            out.append((float(e["t"]), e.get("dir", "tester"), "break", float(e.get("duration", 0.0)),
                        int(e.get("step", 0))))
    out.sort(key=lambda x: x[0])
    return out


def wire_events(transcript: Iterable[dict[str, Any]]) -> list[tuple[float, str, str, Any, int]]:
    """As :func:`wire_runs`, one entry per byte: ``value`` is the byte (an int)."""
    out: list[tuple[float, str, str, Any, int]] = []
    for t, d, kind, value, step in wire_runs(transcript):
        if kind == "break":
            out.append((t, d, kind, value, step))
        else:
            out.extend((t, d, kind, b, step) for b in value)
    return out


def dropped_note(e: dict[str, Any]) -> str:
    """The words for a ``dropped`` entry: bytes the transcript does not keep."""
    who = "the IUT" if e.get("dir") == "iut" else "the tester"
    return (f"{e.get('bytes', 0)} more byte(s) from {who} not kept: the transcript keeps the first "
            f"{e.get('kept', 0)} (flood limit)")

