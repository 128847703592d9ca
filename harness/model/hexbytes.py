"""Bytes as the manual's figures write them (``02 10 03``): the one formatter and parser of
hex text, for every procedure, message and report."""

from __future__ import annotations

from typing import Iterable


def hexstr(data: bytes | bytearray | Iterable[int], limit: int | None = None) -> str:
    """``b'\\x02\\x10'`` -> ``'02 10'``; with ``limit``, at most that many bytes followed by
    ``' ...'`` when there are more."""
    data = bytes(data)
    if limit is not None and len(data) > limit:
        return " ".join(f"{b:02X}" for b in data[:limit]) + " ..."
    return " ".join(f"{b:02X}" for b in data)


def parse_hex(text: str) -> bytes:
    """``'02 10 1003'`` -> bytes. Spaces are optional between bytes; raises ValueError with a
    message that names the offending token."""
    compact = "".join(text.split())
    if len(compact) % 2:
        raise ValueError(f"hex text {text!r} has an odd number of digits")
    try:
        return bytes.fromhex(compact)
    except ValueError:
        raise ValueError(f"hex text {text!r} contains a character that is not a hex digit") from None
