"""How the reports name the bytes of a 3964/3964R link (and of RK 512, which runs on the
3964R link): the control characters that steer the procedure by name, DLE ETX at a block's
end and the BCC after it in 3964R, data in hex; in a divergence's words a lone STX, ETX,
DLE or NAK named; and a block cut short by a new STX drawn as two arrows.

The procedure's part of the reports' :class:`~ptpcert.view.ReportView`:
:func:`report_view` builds it for :meth:`P3964.report_view
<ptpcert.procedures.p3964.description.P3964.report_view>` and RK 512's.
"""

from __future__ import annotations

from typing import Any, Mapping

from ptpcert.procedures.p3964.model.codec import CONTROL_NAMES, DLE, ETX, NAK, STX
from ptpcert.view import ReportView

#: the characters that steer the procedure, by name
CONTROL = CONTROL_NAMES


def tokens(data: bytes, procedure: str = "3964R") -> list[str]:
    """Name the control characters of a burst: a control character that starts a unit (the
    burst, or what follows a block's end) by name, DLE ETX at a block's end, the BCC after
    it in 3964R; data (doubled DLEs included) in hex."""
    out: list[str] = []
    i, n = 0, len(data)
    unit_start = True
    while i < n:
        b = data[i]
        nxt = data[i + 1] if i + 1 < n else None
        if b == DLE and nxt == DLE:
            out += ["10", "10"]
            i += 2
            unit_start = False
            continue
        if b == DLE and nxt == ETX:
            out += ["DLE", "ETX"]
            i += 2
            if procedure == "3964R" and i < n:
                out.append(f"BCC={data[i]:02X}")
                i += 1
            unit_start = True
            continue
        if unit_start and b in CONTROL and (n == 1 or i > 0):
            out.append(CONTROL[b])
            i += 1
            continue
        out.append(f"{b:02X}")
        unit_start = False
        i += 1
    return out


def control_names(params: Mapping[str, Any]) -> Mapping[int, str]:
    """The bytes named in a divergence's words: STX, ETX, DLE and NAK, whatever the case."""
    return CONTROL


def restarts(burst: bytes, answer: bytes) -> bool:
    """A burst that ends in STX (not a data 02 after a DLE) answered by the other side's
    DLE (or NAK, or its own STX) is a block cut short followed by a new STX: the STX is
    drawn as its own arrow."""
    return (len(burst) > 1 and burst[-1] == STX and burst[-2] != DLE
            and answer[:1] in (bytes((DLE,)), bytes((NAK,)), bytes((STX,))))


def report_view(groups: tuple[str, ...], link: str | None = None) -> ReportView:
    """The reports' view of a 3964/3964R link with the case groups ``groups``: ``link``
    ("3964" or "3964R") names the bytes by that procedure's rules; None: by each case's own
    (its params' ``procedure``, 3964R where they name none)."""
    def named(data: bytes, params: Mapping[str, Any]) -> list[str]:
        return tokens(data, link or str(params.get("procedure", "3964R")))
    return ReportView(tokens=named, groups=tuple(groups), names=control_names, cut_last=restarts)
