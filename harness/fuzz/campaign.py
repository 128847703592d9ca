"""The fuzzer's campaign, level 2: generated partner behaviour against an IUT, the model as
oracle.

For every example, hypothesis draws the tester's behaviour step by step through the
procedure's fuzz kit (:class:`ptpcert.fuzz.kit.FuzzKit`), while a model station plays the IUT
in virtual time (co-simulation): what the tester does next depends on what a conforming IUT
has just done. The result is an ordinary vector: the tester's stimuli and, as expectations,
what the model did, with windows derived from why it did it. The vector is run against the
IUT; a divergence is a finding, confirmed by a second run in real time, and not a finding
when a model with another defensible reading of the manual (docs/readings.md) would have done
what the IUT did, or when the IUT may have seen a deliberate interruption only after its block
(:func:`late_violation`). Hypothesis shrinks every finding to a minimal transcript, which is
written out as a vector (``vectors/regressions/``, :func:`export`) that the runner replays.
"""

from __future__ import annotations

import hashlib
import time
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Callable

from hypothesis import Phase, assume, given, settings
from hypothesis import seed as hseed
from hypothesis import strategies as st

from .. import results as R
from ..profile import Profile
from ..runner import Runner, RunOptions
from ..scenario import Vector, dump_vector, expand, load_vector_text
from ..transport import sim_factory
from .database import open_database
from .kit import FuzzKit


@dataclass
class Finding:
    vector: Vector
    result: R.CaseResult
    rule: str
    status: str

    def describe(self) -> str:
        r = self.result
        lines = [f"FINDING {self.vector.id}: {self.rule}",
                 f"  STATUS involved: {self.status or 'none'}",
                 f"  {r.message}"]
        lines.append("  transcript (shrunk):")
        for s in self.vector.steps:
            d = s.to_toml()
            lines.append("    " + ", ".join(f"{k} = {v}" for k, v in d.items()))
        return "\n".join(lines)


class _Found(Exception):
    """Ends a hypothesis example that failed, carrying its finding (shrunk by hypothesis)."""

    def __init__(self, finding: Finding):
        self.finding = finding
        super().__init__(finding.rule)


@dataclass
class Campaign:
    profile: Profile
    runner: Runner
    budget: float
    seed: int
    settings_profile: str = "ptpcert-quick"
    database: str | None = None
    progress: Callable[[str], None] | None = None
    max_actions: int = 6
    examples: int = 0
    informational: int = 0
    #: findings dropped because their exported vector, replayed, did not fail
    not_reproduced: int = 0
    #: failing examples not judged: the tester's deliberate interruption of the IUT's block
    #: may have reached the IUT only after the block (the harness was late), see late_violation
    void: int = 0
    findings: list[Finding] = field(default_factory=list)
    started: float = 0.0
    #: examples whose exchange lasts longer are skipped (None: 2 s + 40 x the longest timer,
    #: which keeps out the 4 s T_BLOCK waits at short timers; level 1 covers those)
    max_case_seconds: float | None = None
    _unshrunk: Finding | None = None
    _shrink_until: float = 0.0
    #: divergences already tried against the other readings (shrinking meets them again)
    _explained: dict = field(default_factory=dict)
    #: one of ``workers`` example streams (see :func:`run_workers`): round ``r`` of worker
    #: ``i`` is seeded ``seed + r * workers + i``, so that the workers' rounds never repeat
    #: one another and one worker's are a serial campaign's
    worker: int = 0
    workers: int = 1

    def _run_vector(self, v: Vector) -> R.CaseResult:
        return self.runner.run_case(v)

    def _release(self) -> None:
        """Stop the IUT processes the transport started ahead, where it does."""
        release = getattr(self.runner.factory, "release", None)
        if release is not None:
            release()

    @property
    def kit(self) -> FuzzKit:
        kit = self.profile.procedure.fuzz_kit()
        if kit is None:
            raise ValueError(f"ptpcert fuzz has no strategies for {self.profile.procedure.title} yet")
        return kit

    def run(self) -> list[Finding]:
        proc, p = self.profile.procedure, self.profile.params
        if self.max_case_seconds is None:
            self.max_case_seconds = 2.0 + 40 * max(proc.edge_timers(p))
        self.started = time.monotonic()
        end = self.started + self.budget
        rnd = 0
        seen_rules: set[str] = set()
        db = open_database(self.database)
        base = settings.get_profile(self.settings_profile)
        over = False
        while time.monotonic() < end and not over:
            gen = self.kit.generator(self.profile, self.max_actions)
            campaign = self
            round_seed = self.seed + rnd * self.workers + self.worker

            # settings outside seed: hypothesis's seed() turns the database off
            @settings(base, max_examples=25, database=db, deadline=None, print_blob=False,
                      phases=[Phase.generate, Phase.shrink] if db is None else list(Phase))
            @hseed(round_seed)
            @given(st.data())
            def example(data):
                nonlocal over
                now = time.monotonic()
                if campaign._unshrunk is None and now >= end:
                    # generating: the budget is spent. The example passes without a draw, so
                    # hypothesis ends the round; raising here would make it a failure, which
                    # hypothesis shrinks and saves in the example database, where a later
                    # campaign would replay it first as if it were a finding
                    over = True
                    return
                if campaign._unshrunk is not None and now >= max(end, campaign._shrink_until):
                    campaign._release()        # no IUT is needed any more in this round
                    return                     # shrinking has had its time: keep what it has
                sim = gen(data)
                # examples that make the IUT wait out T_BLOCK (4 s) cost more real time than
                # they are worth here; level 1 covers those paths in virtual time
                assume(sim.t <= campaign.max_case_seconds)
                digest = hashlib.sha256(repr([s.to_toml() for s in sim.steps]).encode()).hexdigest()[:10]
                v = sim.vector(f"FUZZ.{digest.upper()}", "fuzz example", "")
                campaign.examples += 1
                res = campaign._run_vector(v)
                if res.verdict != R.FAIL:
                    return
                # confirm: real time can glitch once (virtual time cannot)
                virtual = getattr(campaign.runner.factory, "virtual", False)
                res2 = res if virtual else campaign._run_vector(v)
                if res2.verdict != R.FAIL:
                    return
                # in real time, what the IUT saw of a deliberate interruption is judged first
                if not virtual and late_violation(v, res2, interruptions(v), campaign.profile.params.char_time):
                    campaign.void += 1     # the IUT may have seen the interruption after its block
                    return
                alt = campaign._alternative(v, res2)
                if alt:
                    campaign.informational += 1
                    return
                rule, status = divergent_rule(v, res2, campaign.kit)
                found = Finding(v, res2, rule, status)
                if campaign._unshrunk is None:
                    campaign._shrink_until = time.monotonic() + max(10.0, 0.25 * campaign.budget)
                if campaign._unshrunk is None or len(v.steps) < len(campaign._unshrunk.vector.steps):
                    campaign._unshrunk = found
                raise _Found(found)

            self._unshrunk = None
            try:
                example()
            except Exception as exc:
                # a real IUT may not repeat a divergence while hypothesis shrinks it
                # (Flaky): keep the smallest failing example seen, unshrunk
                found = exc if isinstance(exc, _Found) else (_Found(self._unshrunk) if self._unshrunk else None)
                if found is None:
                    if time.monotonic() >= end:
                        break      # hypothesis noticed the budget ending mid-round: nothing lost
                    if self.progress:
                        self.progress(f"round {rnd}: {type(exc).__name__}: {str(exc)[:300]}")
                    rnd += 1
                    continue
                finding = found.finding
                key = finding_key(finding)
                if key not in seen_rules:
                    rid = hashlib.sha256(dump_vector(finding.vector).encode()).hexdigest()[:8].upper()
                    vec = replace(finding.vector, id=f"FUZZ.{rid}", title=f"Fuzz finding: {finding.rule}",
                                  rule=f"{finding.rule} (found by ptpcert fuzz, seed {round_seed})")
                    finding.vector = vec
                    if self.reproduces(finding):
                        seen_rules.add(key)
                        self.findings.append(finding)
                        if self.progress:   # its block (rule, STATUS, transcript) ends the run
                            self.progress(f"finding {finding.vector.id}: {finding.rule}")
                    else:
                        self.not_reproduced += 1
                        if self.progress:
                            self.progress(f"not reproduced (dropped): {finding.vector.id}: {finding.rule}; "
                                          "its exported vector passed on replay")
            finally:
                self._release()   # between rounds no IUT waits: each is started for its example
            rnd += 1
            if self.progress:
                self.progress(f"[{time.monotonic() - self.started:6.1f} s] examples {self.examples}, "
                              f"findings {len(self.findings)}, explained by another reading {self.informational}, "
                              f"not reproduced {self.not_reproduced}, void (interruption late) {self.void}")
        return self.findings

    def reproduces(self, finding: Finding) -> bool:
        """A finding stands only if the vector as exported (written out as TOML and read
        back, as ``ptpcert run --vectors`` reads it) fails under the runner on replay; its
        result then becomes the finding's."""
        try:
            v = load_vector_text(dump_vector(finding.vector), f"<{finding.vector.id}>")
        except ValueError:
            return False   # a vector that cannot be read back cannot stand as a finding
        try:
            res = self._run_vector(v)
        finally:
            self._release()
        if res.verdict != R.FAIL:
            return False
        finding.result = res
        return True

    def _alternative(self, v: Vector, res: R.CaseResult) -> str | None:
        """The open point of the manual (docs/readings.md) whose other reading explains the
        divergence, if any: a model with that reading, run through the same vector, departs
        from it at the same step in the same way as the IUT did."""
        d0 = res.divergence
        key = (d0.expected, d0.observed) if d0 is not None else res.message
        if key not in self._explained:
            self._explained[key] = self._try_alternatives(v, res)
        return self._explained[key]

    def _try_alternatives(self, v: Vector, res: R.CaseResult) -> str | None:
        proc = self.profile.procedure
        app = "echo" if self.profile.echo else "none"
        if app not in proc.apps():
            app = proc.apps()[0]
        for name, change in self.kit.alternatives:
            readings = replace(self.kit.readings, **change)
            factory = sim_factory(proc, {"app": app}, readings=readings)
            alt = Runner(factory, self.profile, RunOptions(check_status=self.kit.check_reports)).run_case(v)
            d = alt.divergence
            if res.divergence is None:
                # a divergence in what the IUT reported (STATUS, request results), not on the wire
                if d is None and alt.verdict == R.FAIL and alt.message == res.message:
                    return name
            elif d is not None and d.step == res.divergence.step and d.observed == res.divergence.observed:
                return name
        return None


def interruptions(v: Vector) -> set[int]:
    """The steps of ``v`` that interrupt the IUT's block: a stimulus followed by the partial
    expectation of what may still come of the block."""
    return {i for i in range(len(v.steps) - 1)
            if v.steps[i].kind in ("send", "send_error", "break") and v.steps[i + 1].kind == "expect"
            and v.steps[i + 1].partial}


def late_violation(v: Vector, res: R.CaseResult, violations, char: float) -> bool:
    """Whether a failing example hinges on a deliberate violation that the IUT may have seen
    only after its block had ended: the IUT sent the whole rest of the block it was meant to
    stop (the partial expectation after the interruption was received to its end), and the
    tester's records cannot prove that the interruption reached the IUT while the block was
    still on the line (a paced block cannot end before the tester's last byte before it plus
    one character time per byte). Then the oracle cannot judge what the IUT saw (the harness
    read the IUT's bytes late and interrupted late): the example is void, not a finding.
    Void too: the IUT stopped inside its block, but later than the window after the
    interruption allows (how fast it stops is real time, not behaviour)."""
    if not violations or res.divergence is None:
        return False
    steps = v.steps
    events = R.wire_events(res.transcript)
    for i in sorted(violations):
        if i >= res.divergence.step or i + 1 >= len(steps) or i < 1:
            continue
        rest, before = steps[i + 1], steps[i - 1]
        if not (rest.kind == "expect" and rest.partial and before.kind == "expect"):
            continue
        after = bytes(b for _, d, kind, b, k in events if d == "iut" and kind == "byte" and k >= i + 1)
        if after[:len(rest.data)] != rest.data:
            # the IUT stopped inside its block: it saw the interruption there; if it only
            # stopped later than the window allows, that is its reaction time on a loaded
            # machine (the suite's cases judge it), not a finding
            if res.divergence.step == i + 1:
                return True
            continue
        sent = [t for t, d, _, _, k in events if d == "tester" and k == i]
        first_iut = [t for t, d, _, _, k in events if d == "iut" and k == i - 1]
        if not sent or not first_iut:
            return True
        released = [t for t, d, _, _, k in events if d == "tester" and t <= first_iut[0] and k < i - 1]
        start = released[-1] if released else 0.0
        end_at_least = start + (len(before.data) + len(rest.data)) * char
        if sent[0] + 2 * char > end_at_least:
            return True
    return False


def finding_key(f: Finding) -> str:
    """Findings with the same key are one finding (the rule and what the model expected)."""
    return f.rule + "|" + (f.result.divergence.expected if f.result.divergence else "")


def divergent_rule(v: Vector, res: R.CaseResult, kit: FuzzKit) -> tuple[str, str]:
    """The rule a failing example broke (named by the note of the step where the IUT
    diverged, through the kit's :attr:`FuzzKit.rule_of_note`) and the STATUS codes involved."""
    steps = expand(v)   # the divergence's step counts the expanded steps (macros unfolded)
    if res.divergence is not None and 0 <= res.divergence.step < len(steps):
        note = steps[res.divergence.step].note
        if note:
            return kit.rule_of_note(note)
    if res.divergence is not None and v.expected.echo_after and any(
            w in (res.divergence.expected or "") for w in ("echo", "block(s)")):
        return "the frames (blocks) sent back are those of a conforming IUT", ""
    if res.divergence is None and res.message.startswith("reported: "):
        return "the IUT's results of its requests follow from the exchange: " + res.message[10:], ""
    if res.divergence is None and res.message.startswith("STATUS: "):
        return "the IUT reports the STATUS events the exchange raises: " + res.message[8:], res.message[8:]
    return "after the exchange the line stays quiet (no spurious bytes)", ""


def export(findings: list[Finding], directory: str | Path) -> list[Path]:
    d = Path(directory)
    d.mkdir(parents=True, exist_ok=True)
    out = []
    for f in findings:
        path = d / f"{f.vector.id.lower().replace('.', '-')}.toml"
        header = (f"Found by ptpcert fuzz: {f.rule}\nSTATUS involved: {f.status or 'none'}\n"
                  f"Divergence: {f.result.message}")
        path.write_text(dump_vector(f.vector, header=header), "utf-8")
        out.append(path)
    return out
