"""What ``ptpcert status`` says of RK 512: the error number (REATEL) of a response frame and
the STATUS events on both sides that go with it (§8.4 Table 8-3)."""

from __future__ import annotations

import sys

from ptpcert.status import short

from .model.codec import STATUS_REATEL, reatels_for_status, status_for_reatel


def reatel_value(text: str) -> int:
    """``34``, ``34h``, ``0x34`` or ``16#34`` -> 0x34 (an RK 512 error number is a byte)."""
    t = text.strip().lower().removeprefix("16#").removeprefix("0x").removesuffix("h")
    value = int(t, 16)
    if not 0 <= value <= 0xFF:
        raise ValueError(text)
    return value


def reatel_text(reatel: int) -> str:
    """REATEL -> STATUS both ways (Table 8-3): the requester's event, the responder's."""
    if reatel == 0:
        return "REATEL 00h: no error (the request is done; the requester reports no event)"
    code = status_for_reatel(reatel)
    listed = code != 0x090E
    lines = [f"REATEL {reatel:02X}h" + ("" if listed else " (not in Table 8-3)"),
             f"  the requester reports 16#{code:04X}  {short(code)}"]
    senders = sorted(c for c, r in STATUS_REATEL.items() if r == reatel)
    if senders:
        lines.append("  the responder sends it for " + ", ".join(f"16#{c:04X} ({short(c)})" for c in senders))
    elif listed:
        lines.append("  no responder event of Table 8-1 sends it (S5 partners do)")
    lines.append("  source     §8.4 Table 8-3")
    return "\n".join(lines)


def reatel_of(code: int) -> str | None:
    """The REATEL line for an RK 512 class-06 or class-09 event (Table 8-3), or None."""
    if code >> 8 == 0x06:
        r = STATUS_REATEL.get(code)
        return (f"  REATEL     the responder answers with {r:02X}h (Table 8-3)" if r is not None
                else "  REATEL     none listed in Table 8-3 (an open point of the manual)")
    if code >> 8 == 0x09:
        rs = reatels_for_status(code)
        return ("  REATEL     raised by " + ", ".join(f"{r:02X}h" for r in rs) + " in the partner's response (Table 8-3)"
                if rs else "  REATEL     any error number Table 8-3 does not list")
    return None


def add_arguments(group) -> None:
    group.add_argument("--reatel", action="append", metavar="HEX",
                       help="RK 512: explain an error number of a response frame (e.g. 34): the event the "
                            "requester reports and the responder's events that send it (Table 8-3); repeatable")


def command(args) -> int | None:
    """``ptpcert status --reatel HEX ...``: each error number explained; 2 where one is not a
    byte in hex."""
    if not getattr(args, "reatel", None):
        return None
    status = 0
    for text in args.reatel:
        try:
            print(reatel_text(reatel_value(text)))
        except ValueError:
            print(f"ptpcert status: --reatel {text!r}: an error number 00..FF in hex (e.g. 34, 34h, 0x34)",
                  file=sys.stderr)
            status = 2
    return status
