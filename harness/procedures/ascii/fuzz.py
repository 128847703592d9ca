"""The fuzzer's ASCII kit: generated partner behaviour against an ASCII IUT, the model as
oracle (``ptpcert fuzz`` with an ASCII profile; the campaign is :class:`ptpcert.fuzz.Campaign`).

For every example hypothesis draws what the tester does, while a model station plays the
IUT in virtual time (co-simulation): frames whose boundaries fall around the CDT, end
characters inside the data and split across a CDT, lengths around the fixed length and
1024, XOFF/XON at any point (inside the tester's own frames and while the IUT sends), parity
errors and BREAK inside frames, bursts that put the receive buffer under pressure (with an
application that reads late, where the profile has the slow_reader setup), and send jobs of
any length with end characters anywhere (where it has the send_job setup). The result is an
ordinary vector: the tester's stimuli, and as expectation the frames a conforming partner
receives back from the model IUT (``echo_after``). A divergence that a model with another
reading of an open point of the manual reproduces is not a finding.

Timing stimuli keep a margin that real time can resolve: a gap "under" the CDT is at most
0.7 of it, one "over" at least 1.5 of it; the exact edges are fuzzed by level 1 (two model
stations in virtual time, tests/test_ascii_fuzz_model.py).
"""

from __future__ import annotations

from dataclasses import fields

from hypothesis import strategies as st

from ptpcert.fuzz.kit import FuzzKit, ms
from ptpcert.model.events import Delivered
from ptpcert.procedures.ascii.model import AsciiHost, AsciiParams, AsciiStation
from ptpcert.procedures.ascii.model.params import MAX_FRAME
from ptpcert.procedures.ascii.model.readings import READINGS, AsciiReadings
from ptpcert.profile import Profile
from ptpcert.scenario import Expected, StatusSpec, Step, Vector

_EPS = 1e-9


class AsciiCoSim:
    """A model ASCII IUT in virtual time and the vector being written while it runs."""

    def __init__(self, profile: Profile, readings: AsciiReadings = READINGS, *, read_delay: float = 0.0,
                 jobs: list[bytes] = ()):
        self.profile = profile
        self.p: AsciiParams = profile.params
        self.char = self.p.char_time
        self.st = AsciiStation(self.p, readings, name="iut")
        self.host = AsciiHost(self.st, "echo" if profile.echo else "none", read_delay=read_delay)
        self.read_delay = read_delay
        self.jobs = list(jobs)
        for job in self.jobs:
            self.st.request_send(0.0, job)
        self.st.power_on(0.0)
        # what a started IUT announces (XON) the runner takes before the steps
        self.out: list[tuple[float, int]] = [(s + self.char, b) for s, b in self.st.pop_output(0.0)]
        skip = len(profile.procedure.startup_bytes(self.p))
        # the runner's steps start once it has the start-up bytes
        start = self.out[skip - 1][0] if skip and len(self.out) >= skip else 0.0
        self.out = self.out[skip:]
        self.delivered: list[bytes] = []
        self._drain()
        self.t = 0.0
        self.advance(start)
        self.ref = start
        self.steps: list[Step] = []

    # -- the model ------------------------------------------------------------------
    def _drain(self) -> None:
        for e in self.host.drain(self.st.now):
            if isinstance(e, Delivered):
                self.delivered.append(e.payload)

    def _collect(self) -> None:
        self.out += [(s + self.char, b) for s, b in self.st.pop_output(self.t)]
        self._drain()
        self.out += [(s + self.char, b) for s, b in self.st.pop_output(self.t)]

    def advance(self, until: float) -> None:
        while True:
            d = self.st.next_deadline()
            if d is None or d > until + _EPS:
                break
            self.t = max(self.t, d)
            self.st.handle_timer(self.t)
            self._collect()
        self.t = max(self.t, until)
        self._collect()

    def _input(self, at: float, kind: str, value: int = 0) -> None:
        self.advance(at - _EPS)
        self.t = max(self.t, at)
        self.st.line_event(at, kind, value)
        self._collect()

    def settle(self, limit: float = 30.0) -> None:
        """Run until the model has nothing left to do (its application included)."""
        end = self.t + limit
        while self.t < end:
            d = self.st.next_deadline()
            if d is None:
                break
            self.advance(max(d, self.t))
        self.advance(self.t + 2 * self.p.cdt + 4 * self.char)

    # -- the tester's side --------------------------------------------------------------
    def send(self, data: bytes, at: float = 0.0, gap: float = 0.0, kind: str = "send", note: str = "") -> None:
        if not data:
            return
        start = self.ref + at
        arrive = start
        for k, b in enumerate(data):
            arrive = start + k * (self.char + gap) + self.char
            self._input(arrive, "invalid" if kind == "send_error" else "byte", b)
        self.ref = arrive
        self.steps.append(Step(kind, bytes(data), at=ms(at), gap=ms(gap), note=note))

    def brk(self, duration: float, at: float = 0.0) -> None:
        t = self.ref + at
        self._input(t, "break")
        self.advance(t + duration)
        self.ref = t + duration
        self.steps.append(Step("break", duration=ms(duration), at=ms(at), note="BREAK"))

    def wait(self, d: float) -> None:
        self.advance(self.ref + d)
        self.ref += d
        self.steps.append(Step("wait", duration=ms(d)))

    # -- the result -----------------------------------------------------------------
    def partner_frames(self) -> list[bytes]:
        """The frames a conforming partner (the tester) receives from what the model IUT
        sent: run one in virtual time on those characters."""
        proc = self.profile.procedure
        partner = AsciiStation(proc.tester_params(self.p), READINGS, name="tester")
        host = AsciiHost(partner, "none")
        if not self.out:
            return []
        partner.power_on(self.out[0][0] - _EPS)
        partner.pop_output()
        got: list[bytes] = []

        def run(until: float) -> None:
            while True:
                d = partner.next_deadline()
                if d is None or d > until + _EPS:
                    return
                partner.handle_timer(max(d, partner.now))
                # what the partner sends (its XON/XOFF) is not part of the expectation; taken
                # off the line, or its pending output would be a deadline for ever
                partner.pop_output(max(d, partner.now))
                got.extend(e.payload for e in host.drain() if isinstance(e, Delivered))
                if partner.next_deadline() == d:
                    return    # nothing moves any more at this instant

        for t, b in self.out:
            run(t - _EPS)
            partner.line_event(max(t, partner.now), "byte", b)
            partner.pop_output(partner.now)
            got.extend(e.payload for e in host.drain() if isinstance(e, Delivered))
        run(self.out[-1][0] + 10 * self.p.cdt + 1.0)
        partner.pop_output()
        return got

    def vector(self, vid: str, title: str, rule: str) -> Vector:
        self.settle()
        frames = self.partner_frames()
        setup = None
        if self.jobs:
            setup = ("send_job", {"jobs": ",".join(j.hex().upper() if j else "-" for j in self.jobs)})
        elif self.read_delay:
            setup = ("slow_reader", {"ms": int(round(self.read_delay * 1000))})
        steps = list(self.steps) or [Step("wait", duration=ms(self.p.cdt))]
        # the tester waits until the model IUT has sent everything (its application may read
        # late): the partner then takes what came, as it came, and no pause between two of
        # the IUT's frames is mistaken for the end of the exchange
        ref = self.ref
        if self.out and self.out[-1][0] > ref:
            steps.append(Step("wait", duration=ms(self.out[-1][0] - ref + 2 * self.char),
                              note="until the IUT has sent back what it will"))
            ref = self.out[-1][0] + 2 * self.char
        if self.out and not frames:
            # nothing a partner takes as a frame (fragments, flow-control codes): the
            # characters themselves, as they came
            t0 = self.out[0][0]
            gaps = [b[0] - a[0] for a, b in zip(self.out, self.out[1:])]
            steps.append(Step("expect", bytes(b for _, b in self.out), after=ms(t0 - ref - 2 * self.char),
                              within=ms(max(0.0, t0 - ref + 2 * self.char)),
                              max_gap=ms(max(gaps, default=0.0) + self.p.cdt),
                              note="what the IUT sent, none of it a frame"))
        return Vector(
            id=vid, title=title, reference="§2.2.4; Figs. 2-20 to 2-23 (generated by ptpcert fuzz)", rule=rule,
            group="regression", iut_role="both", params=self.p, steps=tuple(steps),
            expected=Expected(StatusSpec((), _ALL_ASCII_CODES), StatusSpec(), tuple(self.delivered), (), tuple(frames)),
            requires=frozenset({"echo"} if self.profile.echo and frames else ()), provenance="[fuzz]",
            binds=tuple(f.name for f in fields(AsciiParams) if f.init), procedure="ascii", setup=setup,
        )


def _ascii_codes() -> frozenset[int]:
    from ptpcert.model.codes import Code
    from ptpcert.status import catalogue
    return frozenset({c for c, e in catalogue().items() if "ASCII" in e.protocols and c >> 8 in (7, 8)}
                     | {Code.LEN_ILLEGAL, Code.ABORTED_BY_RESET})


_ALL_ASCII_CODES = _ascii_codes()


# ------------------------------------------------------------------ drawing the tester's behaviour
#: gaps in CDTs: clearly under the CDT (frames merge) or clearly over it (they do not)
UNDER = (0.0, 0.3, 0.7)
OVER = (1.5, 3.0)


class AsciiGenerator:
    """Draws one example: a sequence of tester behaviours, co-simulated with the model."""

    def __init__(self, profile: Profile, max_actions: int = 6, readings: AsciiReadings = READINGS):
        self.profile = profile
        self.p: AsciiParams = profile.params
        self.max_actions = max_actions
        self.readings = readings
        self.line = profile.line_conditions == "parmrk"
        self.xonxoff = self.p.flow_control == "xon_xoff"
        self.can_slow = "slow_reader" in profile.setups
        self.can_jobs = "send_job" in profile.setups

    # -- bytes --------------------------------------------------------------------------
    def _specials(self) -> list[int]:
        p = self.p
        out = [0x00, 0x7F, 0x41]
        if p.end_criterion == "end_chars":
            out += list(p.end_chars)
        if self.xonxoff:
            out += [p.xon, p.xoff]
        return [b & p.code_max for b in out]

    def _data(self, data, n_max: int, label: str, control: bool = False) -> bytes:
        """Data bytes: mostly codes that are data in the profile; ``control``: end characters
        and flow-control codes too (inside the data)."""
        p = self.p
        bad = set()
        if p.end_criterion == "end_chars":
            bad |= set(p.end_chars)
        if self.xonxoff:
            bad |= {p.xon, p.xoff}
        plain = st.integers(0, p.code_max).filter(lambda b: b not in bad)
        byte = st.one_of(plain, st.sampled_from(self._specials())) if control else plain
        return data.draw(st.lists(byte, min_size=1, max_size=n_max).map(bytes), label=label)

    def _frame(self, data) -> bytes:
        """A frame as the criterion delimits it (the tester's view of a good frame)."""
        p = self.p
        if p.end_criterion == "fixed_length":
            n = p.fixed_length
            return bytes((0x41 + i) & p.code_max for i in range(n)) if n > 64 else self._exact(data, n)
        body = self._data(data, 12, "frame data")
        if p.end_criterion == "end_chars":
            return body + p.end_sequence
        return body

    def _exact(self, data, n: int) -> bytes:
        b = self._data(data, n, "fixed frame")
        return (b * (n // len(b) + 1))[:n]

    # -- one example ----------------------------------------------------------------------
    def __call__(self, data) -> AsciiCoSim:
        p = self.p
        read_delay = 0.0
        jobs: list[bytes] = []
        if self.can_slow and data.draw(st.integers(0, 4), label="slow reader") == 0:
            read_delay = data.draw(st.sampled_from([0.3, 1.0]), label="read delay")
        if self.can_jobs and not read_delay and data.draw(st.integers(0, 3), label="send jobs") == 0:
            jobs = data.draw(st.lists(self._job(), min_size=1, max_size=3), label="jobs")
        sim = AsciiCoSim(self.profile, self.readings, read_delay=read_delay, jobs=jobs)
        held = False
        for _ in range(data.draw(st.integers(1, self.max_actions), label="actions")):
            held = self._act(sim, data, held)
            sent = b"".join(s.data for s in sim.steps if s.kind == "send")
            if self.xonxoff:   # an XOFF the tester sent among other characters holds the IUT too
                held = sent.rfind(bytes((p.xoff,))) > sent.rfind(bytes((p.xon,)))
        if held:
            sim.send(bytes((p.xon,)), at=0.5 * p.cdt, note="XON")
        # a last good frame after idle line: whatever came before, the IUT must be receiving again
        sim.send(self._frame(data), at=3 * p.cdt, note="a good frame after idle line")
        return sim

    def _job(self):
        """A send job: LEN 0..1025, end characters anywhere, or a plain frame."""
        p = self.p
        plain = st.lists(st.integers(0x20, min(0x7E, p.code_max)), min_size=1, max_size=16).map(bytes)
        # (XON/XOFF codes in a job are left out: what a driver does with them is open, and no
        # reading of the model covers it)
        codes = [b for b in self._specials() if not (self.xonxoff and b in (p.xon, p.xoff))]
        specials = st.lists(st.sampled_from(codes + [0x41, 0x42]), min_size=0, max_size=12).map(bytes)
        sizes = st.sampled_from([0, 1, MAX_FRAME, MAX_FRAME + 1]).map(lambda n: bytes((0x41,)) * n)
        return st.one_of(plain, specials, sizes)

    def _act(self, sim: AsciiCoSim, data, held: bool) -> bool:
        p = self.p
        kinds = ["frame", "frame", "merge", "split", "fragment", "burst", "wait", "control-inside"]
        if p.end_criterion in ("fixed_length",) or p.end_criterion == "cdt":
            kinds += ["long"]
        if p.end_criterion == "end_chars" and len(p.end_chars) == 2:
            kinds += ["split-end"]
        if self.line:
            kinds += ["char-error", "break"]
        if self.xonxoff:
            kinds += ["xoff", "xoff-inside"]
        kind = data.draw(st.sampled_from(kinds), label="action")
        cdt = p.cdt
        gap_over = data.draw(st.sampled_from(OVER), label="gap over") * cdt
        if kind == "frame":
            sim.send(self._frame(data), at=gap_over, note="a frame")
        elif kind == "merge":   # two parts less than the CDT apart
            a, b = self._frame(data), self._frame(data)
            cut = data.draw(st.integers(1, max(1, len(a))), label="cut")
            sim.send(a[:cut], at=gap_over, note="a frame ...")
            sim.send(a[cut:] + b, at=data.draw(st.sampled_from(UNDER), label="gap under") * cdt,
                     note="... continued within the CDT")
        elif kind == "split":   # a frame cut by a pause longer than the CDT
            a = self._frame(data)
            cut = data.draw(st.integers(1, max(1, len(a))), label="cut")
            sim.send(a[:cut], at=gap_over, note="part of a frame")
            sim.send(a[cut:] or self._frame(data), at=data.draw(st.sampled_from(OVER), label="pause") * cdt,
                     note="the rest, after a pause longer than the CDT")
        elif kind == "fragment":  # too short, too long, end characters inside
            body = self._data(data, 20, "fragment", control=True)
            gap = data.draw(st.sampled_from(UNDER), label="gap inside") * cdt if len(body) > 1 else 0.0
            sim.send(body, at=gap_over, gap=gap if gap < 0.75 * cdt else 0.0, note="characters of any kind")
        elif kind == "burst":   # frames back to back: the buffer under pressure, echoes waiting
            n = data.draw(st.integers(2, 12), label="burst")
            gap = 1.5 * cdt if p.end_criterion == "cdt" else 0.0
            for i in range(n):
                sim.send(self._frame(data), at=gap_over if i == 0 else gap, note=f"burst frame {i + 1}")
        elif kind == "long":    # lengths around the fixed length or 1024
            limit = p.fixed_length if p.end_criterion == "fixed_length" else MAX_FRAME
            n = data.draw(st.sampled_from([limit - 1, limit, limit + 1, limit + 2]), label="length")
            n = max(1, min(n, 1100))
            sim.send(bytes((0x30 + i % 40) & p.code_max for i in range(n)), at=gap_over, note=f"{n} characters")
        elif kind == "split-end":
            e1, e2 = p.end_sequence[:1], p.end_sequence[1:]
            sim.send(self._data(data, 6, "data") + e1, at=gap_over, note="end character 1 ...")
            sim.send(e2, at=data.draw(st.sampled_from(UNDER + OVER), label="pause") * cdt,
                     note="... end character 2")
        elif kind == "wait":
            sim.wait(data.draw(st.sampled_from(UNDER + OVER), label="wait") * cdt)
        elif kind == "control-inside":
            body = self._frame(data)
            k = data.draw(st.integers(0, len(body)), label="position")
            extra = bytes((data.draw(st.sampled_from(self._specials()), label="code"),))
            sim.send(body[:k] + extra + body[k:], at=gap_over, note="a code of any kind inside a frame")
        elif kind == "char-error":
            body = self._frame(data)
            k = data.draw(st.integers(0, len(body) - 1), label="position")
            sim.send(body[:k], at=gap_over, note="a frame ...")
            sim.send(body[k:k + 1], kind="send_error", at=0.0 if k else gap_over, note="a character with a parity error")
            sim.send(body[k + 1:], note="... the rest of it")
        elif kind == "break":
            body = self._frame(data)
            k = data.draw(st.integers(0, len(body)), label="position")
            sim.send(body[:k], at=gap_over, note="part of a frame")
            sim.brk(20 * self.p.char_time, at=0.0 if k else gap_over)
            sim.send(body[k:], at=data.draw(st.sampled_from(UNDER + OVER), label="after break") * cdt,
                     note="characters after the BREAK")
        elif kind == "xoff":    # XOFF now (the IUT may be sending), XON after a hold
            hold = data.draw(st.sampled_from([0.3 * cdt, 2 * cdt, 0.7 * p.xon_wait, 1.5 * p.xon_wait]), label="hold")
            sim.send(bytes((p.xoff,)), at=data.draw(st.sampled_from([0.0, 0.5 * cdt, 1.5 * cdt]), label="xoff at"),
                     note="XOFF")
            if data.draw(st.booleans(), label="xon"):
                sim.send(bytes((p.xon,)), at=hold, note="XON")
                return False
            return True
        elif kind == "xoff-inside":  # XOFF and XON among the data of a frame the tester sends
            body = self._frame(data)
            k = data.draw(st.integers(0, len(body)), label="position")
            sim.send(body[:k] + bytes((p.xoff, p.xon)) + body[k:], at=gap_over, note="XOFF XON inside a frame")
        return held


def generator(profile: Profile, max_actions: int = 6) -> AsciiGenerator:
    return AsciiGenerator(profile, max_actions)


#: the open points whose other reading changes the wire (a divergence it explains is not a finding)
ALTERNATIVE_READINGS = (
    ("Q4", dict(q4_cdt_grace_one_character=False)),
    ("Q6", dict(q6_up_to_end_without_end_sends_all=False)),
    ("Q6", dict(q6_up_to_end_finds_sequence=False)),
    ("Q14", dict(q14_xoff_frame_offset=-1)),
    ("Q15", dict(q15_xon_after_discard=False)),
    ("Q16", dict(q16_xoff_while_idle_holds=False)),
    ("Q16", dict(q16_flow_char_restarts_cdt=True)),
    ("d_hold", dict(d_cdt_suspended_while_holding=False)),
    ("d_break", dict(d_break_aborts_send=True)),
)

FUZZ_KIT = FuzzKit(generator, READINGS, ALTERNATIVE_READINGS)

__all__ = ["ALTERNATIVE_READINGS", "AsciiCoSim", "AsciiGenerator", "FUZZ_KIT", "generator"]
