"""The CP 341 STATUS event catalogue (Tables 8-1 and 8-2), loaded from the package's data
file ``status_catalogue.toml``: lookup by code in any common notation."""

from __future__ import annotations

import re
import tomllib
from dataclasses import dataclass
from functools import lru_cache
from importlib import resources


class UnknownStatus(LookupError):
    """A code that is not in the catalogue, or text that is not a code at all."""


@dataclass(frozen=True)
class StatusEvent:
    code: int
    event_class: str
    class_name: str
    short: str
    text: str
    protocols: tuple[str, ...]
    side: str
    wire_observable: str
    remedy: str
    reference: str

    @property
    def notation(self) -> str:
        return f"16#{self.code:04X}"

    def describe(self) -> str:
        lines = [
            f"{self.notation}  {self.short}",
            f"  class      {self.event_class} ({self.class_name})",
            f"  protocols  {', '.join(self.protocols)}",
            f"  reported   {self.side}",
            f"  on the line {self.wire_observable}",
            f"  source     {self.reference}",
            f"  {self.text}",
        ]
        if self.remedy:
            lines.append(f"  remedy: {self.remedy}")
        return "\n".join(lines)


_CODE = re.compile(r"^(?:16#|0x|0X|W#16#)?([0-9A-Fa-f]{1,4})(?:H|h)?$")


def parse_code(text: str | int) -> int:
    """``'16#0808'``, ``'0x0808'``, ``'0808'``, ``'0808H'`` or 0x0808 -> 0x0808."""
    if isinstance(text, int):
        if not 0 <= text <= 0xFFFF:
            raise UnknownStatus(f"{text} is not a 16-bit STATUS word")
        return text
    m = _CODE.match(text.strip())
    if not m:
        raise UnknownStatus(
            f"{text!r} is not a STATUS code; write it as 16#0808, 0x0808 or 0808"
        )
    return int(m.group(1), 16)


@lru_cache(maxsize=1)
def catalogue() -> dict[int, StatusEvent]:
    raw = tomllib.loads(resources.files("ptpcert").joinpath("status_catalogue.toml").read_text("utf-8"))
    classes = raw["classes"]
    out: dict[int, StatusEvent] = {}
    for e in raw["event"]:
        code = parse_code(e["code"])
        out[code] = StatusEvent(
            code=code,
            event_class=e["class"],
            class_name=classes[e["class"]]["name"],
            short=e["short"],
            text=e["text"],
            protocols=tuple(e["protocols"]),
            side=e["side"],
            wire_observable=e["wire_observable"],
            remedy=e.get("remedy", ""),
            reference=e["reference"],
        )
    return out


def lookup(code: str | int) -> StatusEvent:
    c = parse_code(code)
    try:
        return catalogue()[c]
    except KeyError:
        raise UnknownStatus(
            f"16#{c:04X} is not in the CP 341 catalogue (Tables 8-1, 8-2); "
            f"'ptpcert status --list' shows all {len(catalogue())} codes"
        ) from None


def short(code: int) -> str:
    """Short name for reports; tolerant of codes outside the catalogue."""
    try:
        return lookup(code).short
    except UnknownStatus:
        return "not in the catalogue"
