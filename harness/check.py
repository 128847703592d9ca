"""``ptpcert vectors --check``: replay every vector against the reference model.

The model plays the IUT through the ``sim:`` transport, in virtual time with no timing
tolerance, with the echo application and, where the vector does not need it, without; the
blocks it delivers and completes are checked as well as the bytes, windows and STATUS.
"""

from __future__ import annotations

from dataclasses import dataclass

from . import results as R
from .model import Params3964
from .runner import RunOptions, Runner
from .scenario import Vector
from .transport import Factory
from .transport.sim import SimTransport


@dataclass
class CheckOutcome:
    vector: Vector
    app: str
    result: R.CaseResult

    @property
    def ok(self) -> bool:
        return self.result.verdict in (R.PASS, R.NON_STRICT, R.INFORMATIONAL)


def sim_factory(app: str, buffer_free: bool, station_factory=None) -> Factory:
    def make(v: Vector, params: Params3964):
        tester = (v.tester_params or params)
        return SimTransport(params, app=app, buffer_free=buffer_free, station_factory=station_factory,
                            url=f"sim:?app={app}" + ("" if buffer_free else "&buffer=full"),
                            tester_char=tester.char_time)
    return Factory(make, SimTransport.capabilities, virtual=True)


def check_vector(v: Vector, station_factory=None) -> list[CheckOutcome]:
    apps = ["echo"] if "echo" in v.needs else ["echo", "none"]
    out = []
    for app in apps:
        runner = Runner(sim_factory(app, "buffer_control" not in v.needs, station_factory), None,
                        RunOptions(echo=(app == "echo"), check_model_events=True, virtual=True,
                                   startup_timeout=0.5))
        out.append(CheckOutcome(v, app, runner.run_case(v)))
    return out
