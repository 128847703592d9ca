"""The one results object of a run. JSON is its own format; JUnit, HTML and the console
summary are views of it (:mod:`ptpcert.report`)."""

from __future__ import annotations

import json
from dataclasses import asdict, dataclass, field
from pathlib import Path
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

SCHEMA = "ptpcert-results/1"


def worse_grade(a: str, b: str) -> str:
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
    #: frames the procedure found in the transcript (dir, t0, t1, label), for reports
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

    @property
    def failed(self) -> bool:
        return self.verdict in FAILING


@dataclass
class RunResult:
    tool_version: str
    started: str
    finished: str = ""
    iut: str = ""
    #: the procedure, for people ("3964/3964R", "RK 512", "ASCII driver")
    procedure: str = ""
    profile: dict[str, Any] = field(default_factory=dict)
    profile_path: str = ""
    vector_set: str = ""
    vector_set_hash: str = ""
    cases: list[CaseResult] = field(default_factory=list)
    interrupted: bool = False
    wall_time: float = 0.0
    html_path: str = ""
    schema: str = SCHEMA

    def counts(self) -> dict[str, int]:
        out = {v: 0 for v in VERDICTS}
        for c in self.cases:
            out[c.verdict] = out.get(c.verdict, 0) + 1
        return out

    @property
    def verdict(self) -> str:
        n = self.counts()
        if n[FAIL] or n[XPASS]:
            return FAIL
        if n[ERROR] or self.interrupted:
            return ERROR
        return PASS

    def exit_status(self) -> int:
        v = self.verdict
        return 1 if v == FAIL else 2 if v == ERROR else 0

    # -- JSON -------------------------------------------------------------------------
    def to_dict(self) -> dict[str, Any]:
        d = asdict(self)
        d["counts"] = self.counts()
        d["verdict"] = self.verdict
        return d

    def write_json(self, path: str | Path) -> None:
        p = Path(path)
        p.parent.mkdir(parents=True, exist_ok=True)
        tmp = p.with_suffix(p.suffix + ".tmp")
        tmp.write_text(json.dumps(self.to_dict(), indent=1), "utf-8")
        tmp.replace(p)

    @classmethod
    def from_dict(cls, d: dict[str, Any]) -> "RunResult":
        if d.get("schema") != SCHEMA:
            raise ValueError(f"not a ptpcert results object (schema {d.get('schema')!r}, expected {SCHEMA!r})")
        cases = []
        for c in d["cases"]:
            c = dict(c)
            div = c.pop("divergence", None)
            if div is not None:
                if div.get("window") is not None:
                    div["window"] = tuple(div["window"])
                div = Divergence(**div)
            cases.append(CaseResult(divergence=div, **c))
        fields_ = {k: v for k, v in d.items() if k in cls.__dataclass_fields__ and k != "cases"}
        return cls(cases=cases, **fields_)

    @classmethod
    def read_json(cls, path: str | Path) -> "RunResult":
        try:
            data = json.loads(Path(path).read_text("utf-8"))
        except OSError as exc:
            raise ValueError(f"{path}: cannot be read: {exc.strerror}") from None
        except json.JSONDecodeError as exc:
            raise ValueError(f"{path}: not JSON: {exc}") from None
        try:
            return cls.from_dict(data)
        except (KeyError, TypeError) as exc:
            raise ValueError(f"{path}: not a ptpcert results object ({exc})") from None
