"""How the reports name the bytes of an ASCII driver's line: XON and XOFF by name where the
case's settings have XON/XOFF flow control (with the codes they give, ``xon`` and ``xoff``),
the end characters where the end criterion is the end character(s) (two of them only as the
pair in order, as the driver reads them), every other byte in hex. The driver has no other
control characters: a 02 or a 10 is data.

The procedure's part of the reports' :class:`~ptpcert.view.ReportView`:
:func:`report_view` builds it for :meth:`PAscii.report_view
<ptpcert.procedures.ascii.description.PAscii.report_view>`. ``params`` is a case's
parameters as the results keep them (:meth:`AsciiParams.to_dict
<ptpcert.procedures.ascii.model.params.AsciiParams.to_dict>`); a value that is not a code
(a saved file may hold anything) names nothing.
"""

from __future__ import annotations

from typing import Any, Mapping

from ptpcert.procedures.ascii.model.codec import CONTROL_NAMES
from ptpcert.view import ReportView


def _code(value: Any) -> int | None:
    """A character code 00..FF, or None."""
    if isinstance(value, int) and not isinstance(value, bool) and 0 <= value <= 0xFF:
        return value
    return None


def flow_names(params: Mapping[str, Any]) -> dict[int, str]:
    """XON and XOFF by their codes, where the settings have XON/XOFF flow control."""
    if params.get("flow_control") != "xon_xoff":
        return {}
    codes = {_code(params.get(key)): key.upper() for key in ("xon", "xoff")}
    codes.pop(None, None)
    return codes


def end_sequence(params: Mapping[str, Any]) -> bytes:
    """The end character(s), in order, where the end criterion is the end character(s)."""
    chars = params.get("end_chars")
    if params.get("end_criterion") != "end_chars" or not isinstance(chars, list) or len(chars) not in (1, 2):
        return b""
    codes = [_code(c) for c in chars]
    return b"" if None in codes else bytes(codes)


def end_name(b: int) -> str:
    """An end character's name: ETX, CR, LF...; a printable one as END=xx."""
    return CONTROL_NAMES.get(b, f"END={b:02X}")


def tokens(data: bytes, params: Mapping[str, Any]) -> list[str]:
    """The bytes of a burst: XON/XOFF and the end character(s) by name, the rest in hex."""
    flow, end = flow_names(params), end_sequence(params)
    data = bytes(data)
    out: list[str] = []
    i = 0
    while i < len(data):
        if end and data.startswith(end, i):
            out += [end_name(b) for b in end]
            i += len(end)
            continue
        out.append(flow.get(data[i], f"{data[i]:02X}"))
        i += 1
    return out


def byte_names(params: Mapping[str, Any]) -> dict[int, str]:
    """The bytes named where they stand alone in a divergence's words: XON, XOFF and the
    end characters, as for :func:`tokens`."""
    return {**{b: end_name(b) for b in end_sequence(params)}, **flow_names(params)}


def report_view(groups: tuple[str, ...]) -> ReportView:
    """The reports' view of an ASCII driver's runs with the case groups ``groups``."""
    return ReportView(tokens=tokens, groups=tuple(groups), names=byte_names,
                      codes=frozenset({"xon", "xoff", "end_chars"}))
