"""The small pieces of markup every part of the HTML report uses: text escaped for HTML,
times in milliseconds, bytes in hex, long hex runs in a message shortened, and the verdict
badge.

Part of :mod:`ptpcert.report.html`; standard library only.
"""

from __future__ import annotations

import html as _html
import re
from typing import Any

_HEXRUN_RE = re.compile(r"(?:\b[0-9A-F]{2}\b ){16,}\b[0-9A-F]{2}\b")


def esc(s: Any) -> str:
    """``s`` as text for HTML, quotes escaped too (safe in attributes)."""
    return _html.escape(str(s), quote=True)


def ms(t: float) -> str:
    """Seconds as milliseconds with three decimals (one from 100 s on)."""
    v = t * 1000.0
    return f"{v:.1f}" if abs(v) >= 100000 else f"{v:.3f}"


def ms_short(t: float) -> str:
    """Seconds as milliseconds for a tight label: whole from 100 ms on, else one decimal."""
    v = t * 1000.0
    return f"{v:.0f}" if abs(v) >= 100 else f"{v:.1f}"


def hexstr(data: bytes | bytearray) -> str:
    """``b'\\x02\\x10'`` -> ``'02 10'``."""
    return " ".join(f"{b:02X}" for b in bytes(data))


def abbreviate_hex(text: str, keep_head: int = 8, keep_tail: int = 4) -> str:
    """Shorten long runs of hex bytes in a message ("41 41 ... 41 (1027 bytes)")."""
    def sub(m: re.Match) -> str:
        toks = m.group(0).split()
        return " ".join(toks[:keep_head]) + " … " + " ".join(toks[-keep_tail:]) + f" ({len(toks)} bytes)"
    return _HEXRUN_RE.sub(sub, text)


def badge(verdict: str, extra: str = "") -> str:
    """A verdict as a coloured badge (``extra``: more classes, e.g. "overall")."""
    return f'<span class="v v-{esc(verdict)}{(" " + extra) if extra else ""}">{esc(verdict)}</span>'


def is_num(x: Any) -> bool:
    """A JSON number (true and false are not)."""
    return isinstance(x, (int, float)) and not isinstance(x, bool)
