"""Steps: the moves of a vector's transcript, one at a time.

A vector is a list of steps, each one thing the tester does (send, send with line errors,
break, wait, play a partner) or requires of the IUT (expect bytes within a window, stay
silent), timed by :mod:`ptpcert.scenario.expr` expressions relative to a reference point.
This module defines :class:`Step`, the step kinds common to every procedure
(:data:`STEP_KINDS`) with the keys each may have (:data:`STEP_KEYS`), and a step's TOML
form; a procedure adds its own kinds (macro steps), expanded into these before a run.
Reading a step from TOML, with its errors, is :mod:`ptpcert.scenario.load`'s job.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from .expr import ZERO, Expr
from .hexnotation import vector_hex

#: the step kinds of every procedure; a procedure adds its own (Procedure.macro_steps), which
#: it expands into these before a run
STEP_KINDS = ("send", "send_error", "break", "wait", "expect", "silence", "partner")
#: the step kinds whose value is bytes (the others' is a duration)
DATA_KINDS = ("send", "send_error", "expect")
SINCE = ("previous", "sent", "mark")
GRADES = ("pass", "non-strict", "informational")
#: the keys a step of each of STEP_KINDS may have besides its kind (a procedure's own step
#: kinds name theirs, :attr:`ptpcert.procedure.MacroStep.keys`)
STEP_KEYS = {
    "send": {"at", "gap", "note", "mark"},
    "send_error": {"at", "note", "mark"},
    "break": {"at", "note", "mark"},
    "wait": {"note", "mark"},
    "silence": {"note", "mark"},
    "partner": {"note"},
    "expect": {"after", "within", "max_gap", "partial", "optional", "absent_grade", "or",
               "or_grade", "or_end", "since", "note", "mark", "resume", "skip"},
}


@dataclass(frozen=True)
class Step:
    """One step of a transcript.

    * ``send``: the tester sends ``data`` (``at``: delay before the first byte after the
      reference point; ``gap``: pause between characters on top of the character time).
    * ``send_error``: each byte of ``data`` arrives at the IUT with a parity/framing error.
    * ``break``: the tester holds the line in the space state for ``duration``.
    * ``wait``: the tester does nothing for ``duration``; what arrives is kept for later.
    * ``expect``: the IUT sends ``data``; its first byte arrives in [``after``, ``within``]
      after the reference point and each further byte within ``max_gap`` of the previous
      one. ``partial``: the IUT may stop anywhere in ``data`` (it was interrupted);
      ``optional``: it may send nothing (graded ``absent_grade``); ``alternatives``: other
      byte strings accepted in the same window (graded ``alt_grade``); ``or_end``: where one
      of them came, the case ends after this many further steps (an answer that ends the
      exchange, e.g. a refusal where a service was asked for). ``resume``: the
      bytes continue those of the last ``partial`` step with the same data: only what it
      did not receive is expected (an IUT that was stopped and goes on).
    * ``silence``: the IUT sends nothing for ``duration``.
    * a procedure's own kind (:attr:`ptpcert.procedure.Procedure.macro_steps`): a whole
      exchange with the payload ``data`` (e.g. the tester delivers it as a conforming sender,
      from ``at`` after the reference point, or receives it from the IUT within a window),
      expanded into the steps above by :func:`expand`.
    * ``partner``: for at most ``duration``, the tester plays a conforming station with the
      vector's ``tester_params``, answering whatever the IUT sends, until both are idle and
      the line is quiet (used where the exact bytes depend on timing, e.g. a configuration
      mismatch).

    The reference point of a step is the end of the previous one: after the last byte sent,
    the last byte received, or the end of a wait, silence or break. An expect step with
    ``since = "sent"`` measures from the end of the tester's last byte instead, and with
    ``since = "mark"`` from the end of the last step marked ``mark = true``.
    """

    kind: str
    data: bytes = b""
    at: Expr = ZERO
    gap: Expr = ZERO
    duration: Expr = ZERO
    after: Expr = ZERO
    within: Expr = ZERO
    #: None: the procedure's longest gap between the characters of one transmission
    #: (:attr:`ptpcert.procedure.Procedure.max_gap`)
    max_gap: Expr | None = None
    partial: bool = False
    optional: bool = False
    absent_grade: str = "pass"
    alternatives: tuple[bytes, ...] = ()
    alt_grade: str = "pass"
    since: str = "previous"
    mark: bool = False
    resume: bool = False
    note: str = ""
    #: an optional expect that sees nothing skips this many of the following steps (the
    #: rest of a macro step it begins, e.g. the tester's replies to a block not sent)
    skip: int = 0
    #: where one of ``alternatives`` came: the case ends after this many further steps (None:
    #: it goes on)
    or_end: int | None = None

    @property
    def is_macro(self) -> bool:
        """A procedure's own step kind (expanded before a run)."""
        return self.kind not in STEP_KINDS

    def to_toml(self) -> dict[str, Any]:
        d: dict[str, Any] = {}
        if self.kind in DATA_KINDS or self.is_macro:
            d[self.kind] = vector_hex(self.data)
        else:
            d[self.kind] = str(self.duration)
        if self.at != ZERO and (self.kind in ("send", "send_error", "break") or self.is_macro):
            d["at"] = str(self.at)
        if self.kind == "send" and self.gap != ZERO:
            d["gap"] = str(self.gap)
        if self.kind == "expect" or (self.is_macro and self.within != ZERO):
            if self.since != "previous":
                d["since"] = self.since
            if self.after != ZERO:
                d["after"] = str(self.after)
            d["within"] = str(self.within)
            if self.kind == "expect" and self.max_gap is not None:
                d["max_gap"] = str(self.max_gap)
            if self.partial:
                d["partial"] = True
            if self.optional:
                d["optional"] = True
                if self.absent_grade != "pass":
                    d["absent_grade"] = self.absent_grade
            if self.skip:
                d["skip"] = self.skip
            if self.alternatives:
                d["or"] = [vector_hex(a) for a in self.alternatives]
                if self.alt_grade != "pass":
                    d["or_grade"] = self.alt_grade
                if self.or_end is not None:
                    d["or_end"] = self.or_end
            if self.resume:
                d["resume"] = True
        if self.mark:
            d["mark"] = True
        if self.note:
            d["note"] = self.note
        return d


def unmarked_since(steps) -> int | None:
    """The index of the first step that measures ``since = "mark"`` although no step before
    it sets ``mark = true`` (its window would be anchored at the start of the case); None
    when every such step has its mark. A step's own mark counts only for the steps after it."""
    marked = False
    for i, step in enumerate(steps):
        if step.since == "mark" and not marked:
            return i
        marked = marked or step.mark
    return None
