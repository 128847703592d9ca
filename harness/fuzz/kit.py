"""What a procedure brings to the fuzzer (:class:`FuzzKit`), and the small pieces every
procedure's fuzz kit shares: a measured time as a time expression (:func:`ms`), the STATUS
events a procedure's exchanges may raise besides those an example expects
(:func:`send_receive_codes`), and the rule an expectation's note names (:func:`note_rule`).

The kits themselves live with their procedures (``ptpcert.procedures.<id>.fuzz``); the
campaign that runs them is :mod:`ptpcert.fuzz.campaign`.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable, Sequence

from ..model.codes import Code
from ..scenario import Expr
from ..status import catalogue


def ms(seconds: float) -> Expr:
    """A time the co-simulation measured, as a time expression in milliseconds."""
    if abs(seconds) < 1e-12:
        return Expr("0")
    return Expr(f"{seconds * 1000:.3f}ms")


def send_receive_codes(protocol: str) -> frozenset[int]:
    """Every send/receive event (classes 07 and 08) the catalogue lists for ``protocol`` (as
    the catalogue names it), and the job abort of Table 8-2 (16#1E0D): what a fuzz example
    may see raised besides the events it expects (the catalogue is the one list of codes)."""
    return frozenset({c for c, e in catalogue().items() if protocol in e.protocols and c >> 8 in (7, 8)}
                     | {Code.ABORTED_BY_RESET})


def note_rule(note: str, rules: Sequence[str] = ()) -> tuple[str, str]:
    """The rule an expectation's note names (one of ``rules``, the rules a procedure's model
    writes into its notes, longest first; else the note up to its STATUS list) and the
    STATUS codes it lists."""
    rule = next((r for r in rules if note.startswith(r)), None)
    if rule is None:   # a note the generator wrote itself ("the IUT stops sending its block")
        rule = note.partition(" [STATUS ")[0]
    codes = note[len(rule):].strip()
    if codes.startswith("[STATUS ") and codes.endswith("]"):
        return rule, codes[len("[STATUS "):-1]
    return rule, ""


@dataclass(frozen=True)
class FuzzKit:
    """A procedure's fuzz strategies and oracle: ``generator(profile, max_actions)`` draws
    an example (co-simulated with the model, which is the oracle) and returns an object
    with ``t`` (its length in time), ``steps`` and ``vector(id, title, rule)``; each of
    ``alternatives`` names an open point and the change of ``readings`` that takes its other
    reading, so a divergence that reading explains is not reported as a finding."""

    generator: Callable
    readings: object
    alternatives: tuple[tuple[str, dict], ...]
    #: the examples' expectations include what the IUT reports (STATUS and, for RK 512, the
    #: request results): the campaign checks them where the profile says the IUT reports
    check_reports: bool = False
    #: the rule an expectation's note names and the STATUS codes it lists (a finding is
    #: named by the rule of the step where the IUT diverged)
    rule_of_note: Callable[[str], tuple[str, str]] = note_rule
