"""The tester as a conforming partner: where a case lets it (a ``partner`` step, the
IUT's echo after the steps, the rest of the exchange after a divergence), a model station
of the case's procedure sits in the tester's seat and answers the IUT as the manual has
a partner answer, through the case's own line.

:class:`PartnerPlay` adds this to the case's line (:class:`ptpcert.runner.pump.CaseLine`);
the step interpreter (:mod:`ptpcert.runner.steps`) builds on it. :class:`CaseEndpoint` is
the line as :func:`ptpcert.driver.drive_station` sees it; it notes how late the partner's
replies went out (``partner_late``, ``partner_due``), which the re-judgement of a failed
attempt weighs (:mod:`ptpcert.runner.rejudge`).
"""

from __future__ import annotations

from typing import Any

from ptpcert.driver import Endpoint, drive_station
from ptpcert.model.events import Delivered
from ptpcert.scenario import brief_hex

from .pump import CaseLine


class PartnerPlay(CaseLine):
    """The case's line with a model station that can play the IUT's partner on it."""

    def observe_rest(self) -> None:
        """After a divergence: go on as a conforming partner until the line is quiet, so
        that the whole exchange is on record to be judged (by the model) as it went."""
        self.step_index = len(self.steps)
        v = self.v
        blocks = list(v.expected.echo_after) or list(v.expected.sent) or list(v.expected.delivered) or [b"\x00"]
        limit = self.tr.now() + self.proc.echo_time_limit(self.p, blocks)
        self.play_partner(self.tp, limit, want=None, label="after the divergence: the tester answers as a "
                                                           "conforming partner, for the record")

    def receive_echoes(self, echo: list[bytes]) -> None:
        """After the steps: receive the blocks an echo IUT sends back, as a conforming
        partner, and check them against ``echo``."""
        limit = self.tr.now() + self.proc.echo_time_limit(self.p, echo)
        got = self.play_partner(self.tp, limit, want=len(echo),
                                label="echo: the tester receives as a conforming partner")
        for i, (want, have) in enumerate(zip(echo, got)):
            if want != have:
                self.fail(f"echo {i + 1}: {brief_hex(want)}", f"the IUT sent back {brief_hex(have)}", self.ref)
        if len(got) > len(echo):
            self.fail(f"{len(echo)} block(s) back from the IUT",
                      f"it also sent back {', '.join(brief_hex(x) for x in got[len(echo):])}", self.ref)
        self.forced += sum(len(self.proc.frame(e, self.p)) + 2 for e in echo) * self.char

    def play_partner(self, params: Any, limit: float, want: int | None, label: str) -> list[bytes]:
        """Let a model station in the tester's seat answer the IUT until it has received
        ``want`` blocks (None: until both sides are quiet), or until ``limit``. Returns the
        blocks it received."""
        proc = self.proc
        host = proc.host(proc.station(params, name="tester"), app="none")
        partner = host.station
        start = min(self.rx[self.pos][0] if self.pos < len(self.rx) else self.ref, self.ref)
        partner.power_on(start)
        partner.pop_output()          # it is already running: nothing of its start-up here
        ep = CaseEndpoint(self)
        # quiet for the longest timer, with the lateness a real-time IUT is allowed
        # (the IUT's timers and the partner's: they may differ, e.g. an ASCII partner's CDT)
        quiet = (max(proc.edge_timers(params) + proc.edge_timers(self.p)) + 4 * proc.char_time(params)
                 + self.tol.late(0) + self.lead)
        got: list[bytes] = []

        def on_event(e) -> None:
            if isinstance(e, Delivered):
                got.append(e.payload)

        def stop() -> bool:
            if not proc.partner_done(host):
                return False
            if want is not None and len(got) >= want:
                return True
            # the line has gone quiet: the IUT has nothing more to send (or gave up)
            return ep.now() - ep.last >= quiet

        self.mark("window", t0=self.rel(self.ref), t1=self.rel(limit), label=label)
        drive_station(host, ep, stop=stop, on_event=on_event, until=limit,
                      recheck=lambda: ep.last + quiet)
        if want is not None and len(got) < want:
            self.fail(f"{want} block(s) from the IUT",
                      f"received {len(got)} intact block(s) before the line went quiet", self.tr.now())
        self.ref = max(self.ref, min(self.tr.now(), ep.last))
        return got


class CaseEndpoint(Endpoint):
    """The case's line as an endpoint for a model station in the tester's seat."""

    def __init__(self, run: PartnerPlay):
        self.run = run
        self.last = run.tr.now()

    def now(self) -> float:
        return self.run.tr.now()

    def poll(self, deadline: float) -> list[tuple[float, str, int]]:
        run = self.run
        if run.pos >= len(run.rx):
            run.pump(max(deadline, run.tr.now()))
        items = [(t, "byte", b) for t, b in run.rx[run.pos:]]
        if items:   # consumed (as ``consume`` does each), in one go
            log, step = run.log, run.step_index
            for i in run.rx_log[run.pos:]:
                log[i]["step"] = step
            run.pos = len(run.rx)
            self.last = max(self.last, items[-1][0])
        return items

    def late(self, seconds: float) -> None:
        # the partner's reply went out this late after its model had it due (the harness was
        # busy taking in a long block, or kept from a CPU): a failed attempt is then judged
        # again with the tester's bytes reaching the IUT that much later and more
        # (ptpcert.runner.rejudge)
        run = self.run
        run.partner_late = max(run.partner_late, seconds)
        if seconds > run.tol.stimulus and run.partner_due is None:
            run.partner_due = run.tr.now() - seconds

    def write(self, data: bytes) -> float:
        run = self.run
        w = run.tr.write(data)
        self.last = max(self.last, w)
        for b in data:
            run.record({"t": run.rel(w), "dir": "tester", "kind": "byte", "byte": b, "step": run.step_index})
        return w
