"""The runner: the one blocking driver. It plays the tester's side of a vector against an
IUT behind a transport, with the timing the vector asks for, records everything on the
line, and judges the result.

All waiting happens here, through :meth:`Transport.read` with a deadline; the model never
waits. With the ``sim:`` transport the same code runs in virtual time.

The package, from the bottom up (each module imports only those above it in this list):

- :mod:`~ptpcert.runner.options`: the run's options and the real-time tolerances;
- :mod:`~ptpcert.runner.disturbance`: what the machine did to either process during an
  attempt (stalls, run-queue wait, steal time);
- :mod:`~ptpcert.runner.pump`: the case's line: the byte pump, the transcript, the reading
  position;
- :mod:`~ptpcert.runner.partner`: the tester as a conforming partner (a model station in its
  seat);
- :mod:`~ptpcert.runner.steps`: the step interpreter (:class:`CaseRun`, one vector run once);
- :mod:`~ptpcert.runner.grading`: the IUT's reports, other readings, expected failures;
- :mod:`~ptpcert.runner.rejudge`: a failed real-time attempt judged again by the model;
- :mod:`~ptpcert.runner.attempts`: one case, attempt by attempt;
- :mod:`~ptpcert.runner.run`: a whole run (:class:`Runner`), serial or over workers
  (:mod:`~ptpcert.runner.parallel`).
"""

from .attempts import CaseRunner
from .disturbance import STARVED, MachineWatch, OwnCpuWait, RiseWithin
from .grading import mark_divergence_frame
from .options import VIRTUAL, RunOptions, Tolerance, realtime_tolerance
from .partner import CaseEndpoint, PartnerPlay
from .pump import CaseLine, Flood, StepFailed
from .run import Runner
from .steps import CaseRun, RunnerState, TimingFault, earlier_interrupt

__all__ = [
    "STARVED",
    "VIRTUAL",
    "CaseEndpoint",
    "CaseLine",
    "CaseRun",
    "CaseRunner",
    "Flood",
    "MachineWatch",
    "OwnCpuWait",
    "PartnerPlay",
    "RiseWithin",
    "RunOptions",
    "Runner",
    "RunnerState",
    "StepFailed",
    "TimingFault",
    "Tolerance",
    "earlier_interrupt",
    "mark_divergence_frame",
    "realtime_tolerance",
]
