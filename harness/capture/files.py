"""Capture files: which format a path stands for (:data:`FORMATS`, chosen by name or by
extension, :func:`format_of`), and reading and writing whole files in any of them
(:func:`load`, :func:`save`, and :func:`loads_json` / :func:`dumps` for text and bytes in
memory). The top of :mod:`ptpcert.capture`: it dispatches to the format modules and adds
what files need (telling a results object from a capture JSON by its content, writing
through a temporary file). ``docs/capture-formats.md`` specifies the formats.
"""

from __future__ import annotations

import json
from pathlib import Path

from ptpcert.capture.hexlog import hexlog_text, read_hexlog
from ptpcert.capture.json_format import JSON_FORMAT, from_dict, to_dict
from ptpcert.capture.model import Capture, CaptureError
from ptpcert.capture.pcap import pcap_bytes, read_pcap
from ptpcert.capture.results_format import from_results, from_transcript, to_results

#: Names of the file formats, and the extensions that choose them.
FORMATS = ("json", "results", "hexlog", "pcap")
EXTENSIONS = {".json": "json", ".hexlog": "hexlog", ".log": "hexlog", ".txt": "hexlog",
              ".pcap": "pcap", ".cap": "pcap"}


def format_of(path: str | Path, given: str | None = None) -> str:
    """The format a path stands for: ``given`` when set, else by extension (``.json`` is
    ``json``; :func:`load` then tells a results object from a capture by its content)."""
    if given:
        if given not in FORMATS:
            raise CaptureError(f"unknown format {given!r} (one of {', '.join(FORMATS)})")
        return given
    ext = Path(str(path)).suffix.lower()
    if ext not in EXTENSIONS:
        raise CaptureError(f"cannot tell the format of {str(path)!r} from its extension; name it with "
                           f"--from/--to ({', '.join(FORMATS)}) or use one of {', '.join(EXTENSIONS)}")
    return EXTENSIONS[ext]


def loads_json(text: str, source: str = "", case: str | None = None) -> Capture:
    """A capture JSON, a results object (``case`` selects a case) or a bare transcript."""
    from ptpcert.results.reading import parse_json

    try:
        d = parse_json(text)
    except ValueError as exc:
        raise CaptureError(str(exc), source) from None
    if isinstance(d, dict) and d.get("format") == JSON_FORMAT:
        if case is not None:
            raise CaptureError("a case id selects a case of a results object; this is a capture", source)
        return from_dict(d, source)
    if isinstance(d, dict) and "schema" in d:
        return from_results(d, case, source)
    if isinstance(d, list) and d:
        return from_transcript(d, source=source)
    if isinstance(d, list):   # an empty capture passes every judgement: nothing was read
        raise CaptureError("the JSON is an empty array: no transcript, nothing to read (expected a ptpcert "
                           f"capture ({JSON_FORMAT!r}), a results object or a transcript)", source)
    raise CaptureError(f"neither a ptpcert capture ({JSON_FORMAT!r}) nor a results object", source)


def load(path: str | Path, fmt: str | None = None, case: str | None = None) -> Capture:
    """Read a capture from a file in any of the formats (see :func:`format_of`)."""
    fmt = format_of(path, fmt)
    src = str(path)
    if case is not None and fmt not in ("json", "results"):
        raise CaptureError("a case id selects a case of a results object; a "
                           f"{ {'hexlog': 'hex log'}.get(fmt, fmt)} file has no cases", src)
    try:
        raw = Path(path).read_bytes()
    except OSError as exc:
        raise CaptureError(f"cannot be read: {exc.strerror}", src) from None
    if fmt == "pcap":
        return read_pcap(raw, src)
    try:
        text = raw.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        raise CaptureError(f"not UTF-8 text (byte {exc.start}); is it a pcap file?", src) from None
    if fmt == "hexlog":
        return read_hexlog(text, src)
    return loads_json(text, src, case)


def dumps(cap: Capture, fmt: str, case_id: str = "capture") -> bytes:
    """The capture in format ``fmt``, as the bytes of a file."""
    if fmt == "pcap":
        return pcap_bytes(cap)
    if fmt == "hexlog":
        return hexlog_text(cap).encode()
    if fmt == "json":
        return (json.dumps(to_dict(cap), indent=1, ensure_ascii=False) + "\n").encode()
    if fmt == "results":
        return (json.dumps(to_results(cap, case_id).to_dict(), indent=1) + "\n").encode()
    raise CaptureError(f"unknown format {fmt!r} (one of {', '.join(FORMATS)})")


def save(cap: Capture, path: str | Path, fmt: str | None = None, case_id: str = "capture") -> None:
    """Write a capture to a file (format by ``fmt`` or the extension); written whole to a
    temporary file first, so a failed write leaves no half file."""
    fmt = format_of(path, fmt)
    data = dumps(cap, fmt, case_id)
    p = Path(path)
    if p.exists() and not p.is_file():   # a device, a FIFO: never replaced by a regular file
        raise CaptureError("exists and is not a regular file; give a file name", str(path))
    tmp = p.with_name(p.name + ".tmp")
    try:
        tmp.write_bytes(data)
        tmp.replace(p)
    except OSError as exc:
        tmp.unlink(missing_ok=True)
        raise CaptureError(f"cannot be written: {exc.strerror}", str(path)) from None
