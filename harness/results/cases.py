"""The results of one case: the verdicts a case can get, the first divergence of a failed
case, and :class:`CaseResult` with what the views draw (transcript, frames, steps, STATUS).

The bottom of :mod:`ptpcert.results`: plain data and the verdicts' order, standard library
only. The run that holds the cases is :mod:`ptpcert.results.run`; what a failure looks like
(its frame, its signature) is :mod:`ptpcert.results.failures`.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

PASS = "pass"
FAIL = "fail"
NON_STRICT = "non-strict"
INFORMATIONAL = "informational"
UNSUPPORTED = "unsupported"
XFAIL = "xfail"
XPASS = "xpass"
ERROR = "error"
NOT_RUN = "not-run"

VERDICTS = (FAIL, XPASS, ERROR, NON_STRICT, INFORMATIONAL, PASS, XFAIL, UNSUPPORTED, NOT_RUN)
#: Verdicts that make the run fail (exit status 1); ERROR makes it exit 2.
FAILING = (FAIL, XPASS)
#: Grades of a passing case, mildest first.
GRADE_ORDER = (PASS, INFORMATIONAL, NON_STRICT)


#: The fields of a frame in :attr:`CaseResult.frames` (what
#: :meth:`ptpcert.procedure.Procedure.describe_frames` returns; the reports draw them).
#: Times are seconds on the case's clock, as in the transcript.
FRAME_FIELDS = {
    "dir": 'who sent the frame: "tester" or "iut"',
    "t0": "where the frame begins (its first character, or the answer that opened it)",
    "t1": "where it ends (its last character)",
    "label": "the frame decoded, for people, in the procedure's words",
    "frame": "optional: the frame's content in hex (without the link's framing)",
    "marks": 'optional: named instants inside it, a list of {"t": seconds, "name": str} '
             '(e.g. where an end character came)',
    "windows": 'optional: named spans that belong to it, a list of {"t0", "t1", "name"} '
               '(e.g. the "CDT" after its last character)',
    "diverged": "optional: true when the case's first divergence falls in this frame",
    "expected": "optional: the label of the frame the case expected in its place",
}


def worse_grade(a: str, b: str) -> str:
    """The less mild of two grades of a passing case (:data:`GRADE_ORDER`)."""
    return a if GRADE_ORDER.index(a) >= GRADE_ORDER.index(b) else b


@dataclass
class Divergence:
    """The first point where the IUT did not do what the vector expects."""

    step: int              # index into the expanded steps (-1: prologue/epilogue)
    time: float            # seconds since the case started
    expected: str          # what the step expected, in words and hex
    observed: str          # what happened instead
    window: tuple[float, float] | None = None  # the window that applied (case time)


@dataclass
class CaseResult:
    id: str
    title: str
    reference: str
    rule: str
    group: str
    iut_role: str
    verdict: str = NOT_RUN
    message: str = ""
    divergence: Divergence | None = None
    expected_status: str = ""          # what the IUT must raise (description)
    expected_status_codes: list[list[str]] = field(default_factory=list)
    tester_status: str = ""            # what a CP 341 in the tester's seat raises
    observed_status: list[str] = field(default_factory=list)  # reported by the IUT
    status_checked: bool = False
    transcript: list[dict[str, Any]] = field(default_factory=list)
    #: frames the procedure found in the transcript, for reports: dicts with the fields of
    #: :data:`FRAME_FIELDS` (``dir``, ``t0``, ``t1``, ``label`` always; the rest optional)
    frames: list[dict[str, Any]] = field(default_factory=list)
    steps: list[dict[str, Any]] = field(default_factory=list)  # expanded steps, for reports
    origin: float = 0.0                # the transport clock at the case's time 0 (monotonic)
    duration: float = 0.0              # wall time of the case, seconds
    case_time: float = 0.0             # time on the case's clock (virtual for sim:)
    forced_wait: float = 0.0           # time the protocol itself forces the case to take
    attempts: int = 1
    stderr_tail: str = ""
    readings: list[str] = field(default_factory=list)
    source: str = ""
    params: dict[str, Any] = field(default_factory=dict)
    notes: list[str] = field(default_factory=list)
    rules: list[str] = field(default_factory=list)  # ids of the manual's rules the case checks
    device: str = ""                   # the IUT of a pool (--iut given several times) that ran the case

    @property
    def failed(self) -> bool:
        return self.verdict in FAILING


