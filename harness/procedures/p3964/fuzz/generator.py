"""The 3964(R) fuzz kit's generator (:class:`Generator`): hypothesis draws the tester's
behaviour one action at a time, chosen for the state the co-simulated IUT (:class:`CoSim`)
is in, so what the tester does next depends on what a conforming IUT has just done.

From idle the tester sends blocks (valid, or with a wrong BCC, a character error, a gap
over CDT, a DLE followed by another character, cut short, over-long or stalled), stray
characters, NAKs, BREAKs or waits; it answers the IUT's STX and its block's end with DLE,
NAK, another character, a crossing STX or silence, following a policy drawn per job of the
IUT (answer at random, or refuse the first k attempts so that the attempt limits are
reached); and it interrupts the IUT's block. Timer fractions keep to what a real process
can honour: "just under" is 70 %, "just over" 150 %.
"""

from __future__ import annotations

from hypothesis import strategies as st

from ptpcert.fuzz.kit import ms
from ptpcert.profile import Profile
from ptpcert.scenario import Expr, Step

from ..model import codec
from ..model import table as T
from ..model.readings import READINGS, Readings
from .cosim import CoSim
from .rules import BLOCK_RULE

#: the link's control characters (DLE, STX, ETX, NAK) and 00/FF, drawn more often in payloads
CONTROL_BIAS = [0x10, 0x02, 0x03, 0x15, 0x00, 0xFF]


def payloads(max_size: int = 64):
    """The payload of a tester's block: 1 to ``max_size`` bytes, the link's control
    characters among them more often than chance would put them."""
    byte = st.one_of(st.sampled_from(CONTROL_BIAS), st.integers(0, 255))
    return st.lists(byte, min_size=1, max_size=max_size).map(bytes)


def _timer_fraction(draw, under_only: bool = False) -> float:
    """Fractions of a timer, as close to its edge as a real process can honour."""
    choices = [0.0, 0.2, 0.5, 0.7] + ([] if under_only else [1.5])
    return draw(st.sampled_from(choices))


class Generator:
    """Draws one example: a sequence of tester behaviours, co-simulated with the model."""

    def __init__(self, profile: Profile, max_actions: int = 6, max_payload: int = 64,
                 readings: Readings = READINGS):
        self.profile = profile
        self.p = profile.params
        self.max_actions = max_actions
        self.max_payload = max_payload
        self.readings = readings
        self.line = profile.line_conditions == "parmrk"

    def __call__(self, data) -> CoSim:
        sim = CoSim(self.p, self.profile.echo, self.readings)
        n = data.draw(st.integers(1, self.max_actions), label="actions")
        self._pol, self._policy_job = {"kind": "random"}, None
        for _ in range(n):
            self._act(sim, data)
        self._finish(sim, data)
        return sim

    def _reply_wait(self) -> float:
        """How long the co-simulation waits for the IUT's next move before the tester acts:
        past the longest timer a reply can depend on here (CDT or ADT), not longer."""
        return 2 * max(self.p.cdt, self.p.adt) + 10 * self.p.char_time

    # -- one action, chosen for the situation the model IUT is in ---------------------
    def _act(self, sim: CoSim, data) -> None:
        s = sim.st.state
        if s == T.WAIT_SETUP_ACK:
            return self._answer_setup(sim, data)
        if s == T.SEND_DATA:
            return self._interrupt_block(sim, data)
        if s == T.WAIT_RELEASE_ACK:
            return self._answer_release(sim, data)
        return self._from_idle(sim, data)

    def _from_idle(self, sim: CoSim, data) -> None:
        p = self.p
        kinds = ["block", "block", "bad-block", "bad-block", "stray", "nak", "wait"]
        if self.profile.echo:
            kinds += ["prime", "prime", "prime-long", "prime-long"]
        if self.line:
            kinds += ["break", "char-error"]
        kind = data.draw(st.sampled_from(kinds), label="idle action")
        if kind == "wait":
            sim.wait(data.draw(st.sampled_from([p.cdt * 0.5, p.cdt * 1.5, p.adt * 0.7, p.adt * 1.5])))
        elif kind == "stray":
            sim.send(bytes([data.draw(st.sampled_from([0x41, 0x10, 0x03, 0x00, 0xFF]), label="stray")]),
                     note="a stray character")
        elif kind == "nak":
            sim.send(b"\x15", note="NAK")
        elif kind == "break":
            sim.brk(20 * max(p.char_time, 0.001))
        elif kind == "char-error":
            sim.send(bytes([0x41]), kind="send_error", note="a character with a parity error")
        else:
            if kind == "prime-long":  # long enough to be interrupted, without 02 or 15 in it
                payload = data.draw(st.lists(st.integers(0x20, 0x7E), min_size=60, max_size=160).map(bytes),
                                    label="long payload")
            else:
                payload = data.draw(payloads(self.max_payload), label="payload")
            self._tester_block(sim, data, payload, mutate=(kind == "bad-block"))
            if kind.startswith("prime"):
                sim.uses_echo = True
        sim.run_until_output(1, limit=self._reply_wait())

    def _tester_block(self, sim: CoSim, data, payload: bytes, mutate: bool) -> None:
        p = self.p
        sim.send(b"\x02", note="STX")
        sim.run_until_output(1, limit=self._reply_wait())
        if not (sim.outs and sim.outs[-1].byte == 0x10):
            return  # not answered with DLE (e.g. the IUT is busy): leave it to the next action
        body = codec.body(payload, p.procedure)
        how = data.draw(st.sampled_from(["wrong-bcc", "char-error", "gap", "dle-other", "cut", "too-long", "stall"]
                                        if mutate else ["none"]), label="mutation")
        if how == "stall":  # nothing after the IUT's DLE: its first-character timeout must run out
            return
        if how == "too-long":
            body = codec.body(payload + bytes([0x5A]) * (1025 - len(payload)), p.procedure)
        if how == "wrong-bcc" and p.has_bcc:
            body = body[:-1] + bytes([body[-1] ^ data.draw(st.integers(1, 255), label="bcc xor")])
        if how == "dle-other":
            # a DLE followed by 41 inside the data, with a BCC that is right for what is
            # sent: only the DLE rule (16#0805) can refuse the block
            stuffed = codec.stuff(payload)
            k = data.draw(st.integers(0, len(stuffed)), label="dle position")
            stuffed = stuffed[:k] + b"\x10\x41" + stuffed[k:]
            body = stuffed + b"\x10\x03" + (bytes([codec.bcc(stuffed)]) if p.has_bcc else b"")
        if how == "cut":
            body = body[: data.draw(st.integers(1, len(body) - 1), label="cut")]
        if how in ("char-error", "gap") and len(body) > 1:
            k = data.draw(st.integers(0, len(body) - 1), label="position")
            sim.send(body[:k], note="block") if k else None
            if how == "char-error" and self.line:
                sim.send(body[k:k + 1], kind="send_error", note="a character with a parity error")
            elif how == "gap":
                sim.send(body[k:k + 1], at=(_timer_fraction(data.draw) or 0.7) * p.cdt, note="after a gap")
            else:
                sim.send(body[k:k + 1])
            if body[k + 1:]:
                sim.send(body[k + 1:], note="rest of the block")
        else:
            sim.send(body, note="block" if how == "none" else f"block ({how})")

    # -- the tester's policy for the IUT's current job ---------------------------------
    def _policy(self, sim: CoSim, data) -> dict:
        """Drawn when the IUT starts a job and kept for all its attempts: answer at random,
        or refuse the first k setups / releases / blocks (k up to the attempt limits, so
        that the limits themselves are reached) and cooperate afterwards."""
        job = sim.st.job
        if job is None:
            return {"kind": "random"}
        if getattr(self, "_policy_job", None) is not job:
            self._policy_job = job
            kind = data.draw(st.sampled_from(["random", "random", "refuse"]), label="job policy")
            pol = {"kind": kind}
            if kind == "refuse":
                where = data.draw(st.sampled_from(["setup", "release", "data"]), label="refuse where")
                limit = self.p.setup_attempts if where == "setup" else self.p.transmission_attempts
                pol.update(where=where, how=data.draw(st.sampled_from(["nak", "silence", "other"]), label="refuse how"),
                           left=data.draw(st.one_of(st.just(limit), st.integers(1, limit)), label="refusals"))
            self._pol = pol
        return self._pol

    def _refusal(self, sim: CoSim, data, where: str) -> str | None:
        pol = self._policy(sim, data)
        if pol["kind"] == "refuse" and pol["where"] == where and pol["left"] > 0:
            pol["left"] -= 1
            return pol["how"]
        if pol["kind"] == "refuse":
            return "dle"
        return None

    def _answer(self, sim: CoSim, data, where: str) -> None:
        p = self.p
        sim.advance(max(sim.t, sim.st.busy_until))  # the IUT's STX / block is completely out
        how = self._refusal(sim, data, where)
        if how is None:
            how = data.draw(st.sampled_from(["dle", "dle", "nak", "other", "silence", "stx"]
                                            + (["char-error", "break"] if self.line else [])), label=f"{where} answer")
        at = _timer_fraction(data.draw, under_only=True) * p.adt if how != "silence" else 0.0
        note = {"dle": "DLE", "nak": "NAK", "other": "another character",
                "stx": "a crossing STX (initialization conflict)" if where == "setup" else "STX"}
        if how in ("dle", "nak", "other", "stx"):
            sim.send({"dle": b"\x10", "nak": b"\x15", "other": b"\x41", "stx": b"\x02"}[how], at=at, note=note[how])
        elif how == "char-error":
            sim.send(b"\x10", at=at, kind="send_error", note="DLE with a parity error")
        elif how == "break":
            sim.brk(20 * max(p.char_time, 0.001), at=at)
        sim.run_until_output(1, limit=self._reply_wait())

    def _answer_setup(self, sim: CoSim, data) -> None:
        self._answer(sim, data, "setup")

    def _interrupt_block(self, sim: CoSim, data) -> None:
        """Interrupt the IUT's block after k of its bytes with NAK, another character or a
        BREAK. What may still come of the block is a partial expectation; so that the byte
        that follows it (a new STX, a NAK) cannot be mistaken for block data, the block must
        not contain those values within the bytes that may still be on their way."""
        p = self.p
        st_ = sim.st
        forced = self._refusal(sim, data, "data")
        if forced in ("nak", "other"):
            how = forced
        elif forced is not None:
            how = "nothing"
        else:
            how = data.draw(st.sampled_from(["nothing", "nak", "other"] + (["break"] if self.line else [])),
                            label="interrupt")
        body = st_.block_body(st_.job.payload) if st_.job else b""
        end = st_.block_done_at
        if how == "nothing" or p.char_time == 0 or len(body) < 16 or end is None:
            sim.advance(end if end is not None else sim.t)
            return
        start = end - len(body) * p.char_time
        done = max(1, int(round((sim.t - start) / p.char_time)))
        if done > len(body) - 12:
            sim.advance(end)
            return
        k = data.draw(st.integers(done, len(body) - 12), label="interrupt after")
        window = body[k:k + 64]
        if 0x02 in window or 0x15 in window:
            sim.advance(end)
            return
        sim.advance(start + k * p.char_time + 1e-9)   # the k-th byte of the block is complete
        sim.flush_expectations()
        # a deliberate violation: it goes out while the IUT is still sending its block
        if how == "break":
            sim.brk(20 * p.char_time, violation=True)
        else:
            sim.send(b"\x15" if how == "nak" else b"\x42", note="NAK" if how == "nak" else "another character",
                     violation=True)
        stim = sim.ref
        sim.advance(max(sim.t, st_.popped_until, st_.busy_until if st_.state is not T.SEND_DATA else sim.t))
        rest_sent = [o for o in sim.outs if o.rule == BLOCK_RULE]
        sim.outs = [o for o in sim.outs if o.rule != BLOCK_RULE]
        # what may still come of the block is measured from its k-th byte (the mark before
        # the interruption): it may be on its way before the interruption has gone out
        mark_ref, _ = sim.since_mark()
        sim.steps.append(Step("expect", body[k:], partial=True, since="mark", after=ms(0.0),
                              within=Expr(f"{ms(max(stim - mark_ref, 0.0)).text} + 4*CHAR"),
                              note="§7.2 items 3-4, §7.6: the IUT stops sending its block"))
        if rest_sent:
            sim.ref = max(sim.ref, rest_sent[-1].t)
        sim.run_until_output(1, limit=self._reply_wait())

    def _answer_release(self, sim: CoSim, data) -> None:
        self._answer(sim, data, "release")

    def _finish(self, sim: CoSim, data=None) -> None:
        """Bring the exchange to rest: the tester goes on answering whatever the IUT still
        wants to send, following the job's policy and then as a conforming partner, until
        the IUT is idle (or waits for a repetition, which looks the same on the line)."""
        st_ = sim.st
        for _ in range(20 * self.p.setup_attempts * self.p.transmission_attempts):
            s = st_.state
            if s in (T.WAIT_SETUP_ACK, T.WAIT_RELEASE_ACK):
                if data is not None:
                    self._answer(sim, data, "setup" if s == T.WAIT_SETUP_ACK else "release")
                else:
                    sim.advance(max(sim.t, st_.busy_until))
                    sim.send(b"\x10", note="DLE (the tester accepts)")
            elif s == T.SEND_DATA and data is not None:
                self._interrupt_block(sim, data)
            elif s in (T.IDLE, T.WAIT_REPETITION) and not st_.transmitting and st_.pending_jobs == 0:
                break
            else:
                d = st_.next_deadline()
                if d is None:
                    break
                sim.advance(max(d, sim.t))
