"""The rules the RK 512 fuzz kit's expectations name, and how a finding's note is read back
(:func:`rule_of_note`): what the IUT sends is named by the rule that makes a conforming
station send it, in the words the line analysis uses for the same rule
(:mod:`ptpcert.procedures.rk512.analysis.judging`; for the 3964(R) link below, the rules of
its transition table), followed by ``; here:`` and what this step shows. A finding is thus
named by the rule, never by a step's own description.
"""

from __future__ import annotations

from ptpcert.fuzz.kit import note_rule
from ptpcert.procedures.p3964.model import table as T
from ptpcert.procedures.rk512.analysis.judging import (COMMAND_RULE, CONTINUATION_RULE, RESPONSE_RULE,
                                                       UNASKED_RULE)
from ptpcert.procedures.rk512.model.codec import Kind, classify, describe


def _text(rule: tuple[str, str]) -> str:
    return f"{rule[0]} ({rule[1]})"


def _link_rule(rule_id: str) -> str:
    elements = [r for _, _, r in T.rows()] + [b for _, b in T.branches()]
    return T.rule_text(next(e for e in elements if e.rule and e.rules and e.rules[0] == rule_id))


RESPONSE = _text(RESPONSE_RULE)
COMMAND = _text(COMMAND_RULE)
CONTINUATION = _text(CONTINUATION_RULE)
#: the IUT stays quiet where it owes nothing
QUIET = _text(UNASKED_RULE)
SETUP_STX = _link_rule("3964.TX.SETUP-STX")
LOW_DEFERS = _link_rule("3964.CONFLICT.LOW-DEFERS")
HIGH_WAITS = ("at an initialization conflict the high-priority station does not answer the partner's STX; it "
              "waits for the partner to defer with DLE (§2.2.2 Initialization conflict; Fig. 2-8)")
LINK_ANSWER = ("below RK 512 a station answers the partner's link characters as a 3964(R) station does: DLE "
               "to take a block, NAK to refuse one or when a timer runs out (§2.2.2; §2.2.3)")
#: a divergence at a step that names no rule (one of the tester's own)
UNNAMED = "the IUT sends what a conforming RK 512 station on its 3964(R) link sends here (the reference model)"

RULES = tuple(sorted((RESPONSE, COMMAND, CONTINUATION, QUIET, SETUP_STX, LOW_DEFERS, HIGH_WAITS, LINK_ANSWER),
                     key=len, reverse=True))


def note(rule: str, here: str = "") -> str:
    """An expectation's note: the ``rule`` and what this step shows of it."""
    return rule + (f"; here: {here}" if here else "")


def frame_note(frame: bytes) -> str:
    """The note of a frame the IUT sends: the rule that makes a conforming station send it."""
    kind = classify(frame)
    if kind is Kind.COMMAND:
        return note(COMMAND, "the IUT's request is " + describe(frame))
    if kind is Kind.CONTINUATION:
        return note(CONTINUATION, "the IUT's request goes on with " + describe(frame))
    return note(RESPONSE, "the IUT answers with " + describe(frame))


def rule_of_note(text: str) -> tuple[str, str]:
    """The rule a note names (one of :data:`RULES`; :data:`UNNAMED` for a note of the
    tester's) and the STATUS codes it lists."""
    rule, codes = note_rule(text, RULES)
    return (rule if rule in RULES else UNNAMED), codes
