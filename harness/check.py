"""``ptpcert vectors --check``: replay every vector against the reference model.

The model plays the IUT through the ``sim:`` transport, in virtual time with no timing
tolerance, with the echo application and, where the vector does not need it, without; the
blocks it delivers and completes are checked as well as the bytes, windows and STATUS.
Where the procedure can, the tester's own script is replayed by a model too.
"""

from __future__ import annotations

from dataclasses import dataclass

from . import results as R
from .runner import RunOptions, Runner
from .scenario import Vector
from .transport import sim_factory


@dataclass
class CheckOutcome:
    vector: Vector
    app: str
    result: R.CaseResult

    @property
    def ok(self) -> bool:
        return self.result.verdict in (R.PASS, R.NON_STRICT, R.INFORMATIONAL)


def check_vector(v: Vector, mutant: str | None = None) -> list[CheckOutcome]:
    """The vector against the model as IUT (each application it allows; a broken variant
    with ``mutant``) and, where both sides send, the tester's script against a model in the
    tester's seat."""
    out = _check_as_iut(v, mutant)
    both = check_both_sides(v) if mutant is None else None
    return out + ([both] if both is not None else [])


def _check_as_iut(v: Vector, mutant: str | None = None) -> list[CheckOutcome]:
    proc = v.proc
    apps = ["echo"] if "echo" in v.needs else list(proc.apps())
    out = []
    for app in apps:
        options = {"app": app}
        if mutant:
            options["mutant"] = mutant
        url = "sim:?" + "&".join(f"{k}={x}" for k, x in options.items())
        runner = Runner(sim_factory(proc, options, url=url), None,
                        RunOptions(echo=(app == "echo"), check_model_events=True, startup_timeout=0.5))
        out.append(CheckOutcome(v, app, runner.run_case(v)))
    return out


def check_both_sides(v: Vector) -> CheckOutcome | None:
    """The procedure's replay of the tester's own script (3964: the crossing STXs of Fig.
    2-8 between two model stations), or None where that does not apply."""
    outcome = v.proc.cross_check(v)
    if outcome is None:
        return None
    verdict, message = outcome
    res = R.CaseResult(v.id, v.title, v.reference, v.rule, v.group, v.iut_role,
                       verdict={"pass": R.PASS, "fail": R.FAIL}.get(verdict, R.ERROR), message=message)
    return CheckOutcome(v, "both sides", res)
