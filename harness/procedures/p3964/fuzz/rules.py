"""The rules the 3964(R) fuzz kit's expectations name: every rule of the transition table
(:mod:`ptpcert.procedures.p3964.model.table`) whose row or decision outcome makes a station
send, the rule a byte the model sent stands for (:func:`rule_for`), the note an expectation
carries (:func:`expectation_note`) and how a finding's note is read back
(:func:`rule_of_note`).

The co-simulation (:mod:`.cosim`) writes these rules into the notes of the expectations it
derives from the model; the campaign reads them back to name a finding by the rule of the
step where the IUT diverged.
"""

from __future__ import annotations

from ptpcert.fuzz.kit import note_rule

from ..model import table as T

#: every rule an expectation can name: the rows and decision outcomes of the table that send
_RULES = sorted({T.rule_text(e) for e in [r for _, _, r in T.rows()] + [b for _, b in T.branches()] if e.rule},
                key=len, reverse=True)
BLOCK_RULE = T.rule_text(T.TABLE[T.WAIT_SETUP_ACK][T.DLE])
UNEXPLAINED_RULE = "the reference model's behaviour"


def rule_for(actions: list[str], byte: int) -> str:
    """The manual's rule that makes a conforming station send ``byte`` after running
    ``actions`` (the table row's action and the decisions taken, as the station's explain log
    records them): the rule and reference of the row or decision outcome that sends it."""
    element = T.rule_for(actions, byte)
    return UNEXPLAINED_RULE if element is None else T.rule_text(element)


def rule_of_note(note: str) -> tuple[str, str]:
    """The rule an expectation's note names (one of the table's, when a rule of the model
    made it) and the STATUS codes it lists."""
    return note_rule(note, _RULES)


def expectation_note(rule: str, codes) -> str:
    """The note of an expectation: its ``rule``, and the STATUS ``codes`` the model raised
    with it in brackets (the form :func:`rule_of_note` reads back)."""
    return rule + (" [STATUS " + ", ".join(f"16#{c:04X}" for c in codes) + "]" if codes else "")
