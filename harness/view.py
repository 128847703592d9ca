"""What the views need to know about a procedure, handed in by the caller: a
:class:`ReportView`. The reports themselves name no procedure; a procedure describes its
view (:meth:`ptpcert.procedure.Procedure.report_view`) and the command line hands it to
:func:`ptpcert.report.html.write_html`.

Without a view a run is shown neutrally: each byte in hex, the case groups in the order
they appear in the run, no byte named in a divergence's words, no burst cut.

A leaf of the import graph, standard library only: the procedures' descriptions make views,
the reports (:mod:`ptpcert.report`) draw with them.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from typing import Any, Callable, Mapping

#: a byte in hex that stands alone in a text (not a time, not part of a word or a code)
_LONE_HEX_RE = re.compile(r"(?<![\w.#-])([0-9A-F]{2})(?![\w.])(?!\s*m?s\b)")


def hex_tokens(data: bytes, params: Mapping[str, Any] | None = None) -> list[str]:
    """Each byte in hex: ``b'\\x02A'`` -> ``['02', '41']``."""
    return [f"{b:02X}" for b in bytes(data)]


def no_names(params: Mapping[str, Any]) -> Mapping[int, str]:
    """No byte has a name."""
    return {}


def never_cut(burst: bytes, answer: bytes) -> bool:
    """No burst is cut."""
    return False


def name_bytes(text: str, names: Mapping[int, str]) -> str:
    """'received 02' -> 'received 02 (STX)' with ``names`` {0x02: "STX"}: name a byte that
    stands alone in ``text`` (not inside a run of hex bytes)."""
    if not names:
        return text

    def sub(m: re.Match) -> str:
        a, b = m.start(), m.end()
        before, after = text[max(0, a - 3):a], text[b:b + 3]
        if re.fullmatch(r"[0-9A-F]{2} ", before) or re.fullmatch(r" [0-9A-F]{2}", after):
            return m.group(0)
        name = names.get(int(m.group(1), 16))
        return f"{m.group(1)} ({name})" if name else m.group(0)
    return _LONE_HEX_RE.sub(sub, text)


@dataclass(frozen=True)
class ReportView:
    """How the reports show the runs of one procedure.

    ``tokens(data, params)``: the bytes of one burst as the labels of an arrow, ``params``
    being the case's parameters (:attr:`ptpcert.results.CaseResult.params`).
    ``groups``: the case groups in the manual's order; groups not listed follow, sorted;
    empty: the order in which they appear in the run.
    ``names(params)``: bytes named where they stand alone in a divergence's words
    ("received 15 (NAK)").
    ``cut_last(burst, answer)``: whether a burst's last byte is drawn as an arrow of its own
    because it starts anew, ``answer`` being the other side's burst right after it (3964: a
    block cut short by a new STX that the partner answers).
    """

    tokens: Callable[[bytes, Mapping[str, Any]], list[str]] = hex_tokens
    groups: tuple[str, ...] = ()
    names: Callable[[Mapping[str, Any]], Mapping[int, str]] = no_names
    cut_last: Callable[[bytes, bytes], bool] = never_cut
    #: the profile keys whose values are character codes (shown in hex)
    codes: frozenset[str] = frozenset()

    def settings(self, profile: Mapping[str, Any]) -> list[tuple[str, str]]:
        """A run's profile (as :meth:`ptpcert.profile.Profile.to_dict` gives it) as
        ``(key, value)`` rows in the profile file's words: ``table.key`` for a key of a
        procedure's table (``iut.setups.NAME`` for a setup), each value as the profile writes
        it (character codes in hex, ``true``/``false``, strings in quotes)."""
        rows: list[tuple[str, str]] = []
        for key, value in profile.items():
            if key == "expected_failures":
                continue
            if isinstance(value, Mapping):
                table = "iut.setups" if key == "setups" else key
                rows += [(f"{table}.{k}", _literal(v, k in self.codes)) for k, v in value.items()]
            else:
                rows.append((key, _literal(value, key in self.codes)))
        return rows

    def words(self, text: str, params: Mapping[str, Any]) -> str:
        """``text`` with the bytes that :attr:`names` names named where they stand alone."""
        return name_bytes(text, self.names(params))

    def order(self, present: list[str]) -> list[str]:
        """The groups ``present`` (in their order of appearance) in the order to show them."""
        if not self.groups:
            return list(present)
        ordered = [g for g in self.groups if g in present]
        return ordered + sorted(g for g in present if g not in self.groups)


def _literal(value: Any, code: bool = False) -> str:
    """``value`` as a profile file writes it; ``code``: integers as character codes."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int) and code:
        return f"0x{value:02X}"
    if isinstance(value, float):
        return f"{value:g}"
    if isinstance(value, str):
        return '"' + value.replace("\\", "\\\\").replace('"', '\\"') + '"'
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(_literal(v, code) for v in value) + "]"
    return str(value)


#: the view of a run whose procedure is not known
NEUTRAL = ReportView()
