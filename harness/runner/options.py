"""What a run is told: :class:`RunOptions` (retries, confirmation, flood limit, what is
judged) and the real-time :class:`Tolerance` it carries, how far the IUT's timing may stray
from a window and how late the tester's own stimuli may go out.

The lowest layer of :mod:`ptpcert.runner`: plain values, no transport and no waiting. An
option left as None (``tolerance``) is filled per attempt by the case runner
(:mod:`ptpcert.runner.attempts`): :data:`VIRTUAL` in virtual time, else
:func:`realtime_tolerance` of the procedure's timers.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any


@dataclass(frozen=True)
class Tolerance:
    """How far the IUT's timing may stray from a window, and how late the tester's own
    stimuli may be before the case is void (a harness timing fault, retried)."""

    early: float        # a reply may come this much before its window opens,
    early_rel: float    # ... plus this fraction of the window's nominal lower bound
    late_abs: float     # ... and this much after it closes,
    late_rel: float     # ... plus this fraction of the window's nominal upper bound
    stimulus: float     # the tester's bytes may go out this late
    #: how late an output that one of the IUT's own timers causes may come beyond the
    #: above (the profile's declared ``timer_tolerance_ms``): widens only the late side of
    #: a window whose lower bound is an IUT timer
    iut_timer: float = 0.0

    def late(self, nominal: float) -> float:
        return self.late_abs + self.late_rel * max(nominal, 0.0)


#: the tolerances in virtual time, where the model keeps every timing exactly: rounding only
VIRTUAL = Tolerance(early=1e-9, early_rel=0.0, late_abs=1e-9, late_rel=0.0, stimulus=1e-6)


def realtime_tolerance(proc, params: Any, late_ms: float = 50.0) -> Tolerance:
    """Tolerances for real processes on a loaded machine: one character time plus 1 ms plus
    10 % early (the IUT may time from when it read our byte, not from its stop bit, and the
    harness may read the byte that starts a window a little late); 50 ms plus 25 % late;
    the tester's stimuli at most 15 % of the IUT's shortest timer late."""
    char = proc.char_time(params)
    return Tolerance(
        early=char + 0.001,
        early_rel=0.10,
        late_abs=late_ms / 1000.0 + 2 * char,
        late_rel=0.25,
        stimulus=max(0.002, 0.15 * min(proc.edge_timers(params))),
    )


@dataclass
class RunOptions:
    """How the runner runs and judges the cases of one run (the command line's and the
    pytest plugin's settings)."""

    tolerance: Tolerance | None = None
    late_ms: float = 50.0
    startup_timeout: float = 2.0      # how long a freshly started IUT may take to say NAK
    timing_retries: int = 3           # reruns of a case voided by a harness timing fault
    confirm_late: bool = True         # reproduce a failure that the machine's timing may have caused
    edge_attempts: int = 4            # attempts in all for a failing case close to a timer's edge
    retry_pause: tuple[float, ...] = (0.2, 0.5, 1.0)  # seconds before the 1st, 2nd, 3rd+ repeat
    flood_limit: int = 20_000         # bytes from the IUT in one case before it counts as flooding
    echo: bool = True                 # the IUT echoes received blocks (profile send_trigger)
    check_status: bool = True         # compare reported STATUS events (profile status_from_stderr)
    check_model_events: bool = False  # sim: also check deliveries and completed jobs
    #: a failed real-time attempt is re-judged by the model fed the line as it was (see
    #: ptpcert.replay): a failure the harness's own timing explains is void, not the IUT's
    rejudge: bool = True
    #: a failed case whose tagged open points (``readings``) have another reading that
    #: explains the divergence is graded by that reading's grade (Procedure.reading_grade)
    grade_readings: bool = True
