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
    """The vector against the model as IUT (each application it allows) and, where both
    sides send, the tester's script against a model in the tester's seat."""
    out = _check_as_iut(v, station_factory)
    both = check_both_sides(v) if station_factory is None else None
    return out + ([both] if both is not None else [])


def _check_as_iut(v: Vector, station_factory=None) -> list[CheckOutcome]:
    apps = ["echo"] if "echo" in v.needs else ["echo", "none"]
    out = []
    for app in apps:
        runner = Runner(sim_factory(app, "buffer_control" not in v.needs, station_factory), None,
                        RunOptions(echo=(app == "echo"), check_model_events=True, virtual=True,
                                   startup_timeout=0.5))
        out.append(CheckOutcome(v, app, runner.run_case(v)))
    return out


def check_both_sides(v: Vector) -> CheckOutcome | None:
    """Where both sides send and their STXs cross (``iut_role = "both"``: Fig. 2-8), the
    tester's script is itself checked: two model stations wired together - the IUT with the
    job the vector primes and its echo application, the tester (the other priority) with the
    block it sends, its STX crossing the IUT's - must put exactly the vector's bytes on the
    line, in its order, and deliver what it says. None where that does not apply (one
    sender, a vector without a primed job of the IUT - e.g. a fuzz finding, where the IUT
    sends only by echo - or an STX the script sends well after the IUT's, which is a stimulus)."""
    from .model import Station3964, codec
    from .model.events import Delivered
    from .model.link import Link
    from .scenario import expand, timer_env

    primes = [s for s in v.steps if s.kind == "prime"]
    if v.iut_role != "both" or not primes:
        return None  # the IUT sends only what its echo application answers: no crossing of own jobs
    res = R.CaseResult(v.id, v.title, v.reference, v.rule, v.group, v.iut_role, verdict=R.PASS)
    steps = [s for s in expand(v) if s.kind in ("send", "expect")][4 * len(primes):]
    try:
        own = primes[0].data
        first = next(i for i, s in enumerate(steps) if s.kind == "send")
        stx_at = steps[first].at.eval(timer_env(v.params))
        theirs = codec.parse_body(next(s.data for s in steps[first:] if s.kind == "send" and len(s.data) > 2),
                                  v.params.procedure)
    except (StopIteration, IndexError, codec.FrameError) as exc:
        res.verdict, res.message = R.ERROR, f"both sides: no crossing setup to replay in the script ({exc})"
        return CheckOutcome(v, "both sides", res)
    if stx_at > 0:
        return None  # an STX sent after the IUT's has arrived is a stimulus, not a crossing
    tester_params = v.tester_params or v.params.with_(priority="high" if v.params.priority == "low" else "low")
    iut, tester = Station3964(v.params, name="iut"), Station3964(tester_params, name="tester")
    link = Link(iut, tester, echo={"iut"})
    link.power_on(0.0)
    link.run_until_quiet(1.0)
    t0 = link.now
    link.request(iut, own, at=t0)
    # the STXs cross: the tester's starts just before the IUT's has reached it, when the
    # script sends it (at once after receiving the IUT's, one character later on the line)
    link.request(tester, theirs, at=t0 + v.params.char_time * (1 - 1e-6))
    link.run_until_quiet(t0 + 600.0)
    got = [(w.src, w.byte) for w in link.wire if w.start >= t0 - 1e-9]
    want = [("tester" if s.kind == "send" else "iut", b) for s in steps for b in s.data]
    if got[:len(want)] != want:
        i = next((k for k, (a, b) in enumerate(zip(got, want)) if a != b), min(len(got), len(want)))
        show = lambda x: f"{x[0]} {x[1]:02X}" if x else "nothing"  # noqa: E731
        res.verdict = R.FAIL
        res.message = (f"both sides: byte {i + 1} of the exchange is {show(want[i] if i < len(want) else None)} "
                       f"in the script, {show(got[i] if i < len(got) else None)} between two model stations")
    delivered = [own] + [e.payload for e in link.events_of(iut, Delivered)]
    echoed = [e.payload for e in link.events_of(tester, Delivered)]
    if res.verdict == R.PASS and (delivered != list(v.expected.delivered)
                                  or echoed[1:] != list(v.expected.echo_after)):
        res.verdict = R.FAIL
        res.message = ("both sides: the model stations deliver " + ", ".join(codec.hexstr(x) for x in delivered)
                       + " / echo " + ", ".join(codec.hexstr(x) for x in echoed[1:]))
    return CheckOutcome(v, "both sides", res)
