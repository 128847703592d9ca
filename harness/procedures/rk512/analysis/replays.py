"""The frame layer's alternatives: a seat's RK 512 layer replayed with what the line does not show.

The part of :class:`~ptpcert.procedures.rk512.analysis.analyzer.Rk512Analyzer` that reuses the
model's decisions (:class:`Replays`, mixed into it). Where a seat's response, continuation or
command differs from what its probes say it owes, the frame layer
(:mod:`~ptpcert.procedures.rk512.analysis.judging`) asks for the alternatives: what the
passive or the active side took since it was last at rest (the frame layer's logs) replayed
on fresh probes (:mod:`~ptpcert.procedures.rk512.analysis.probe`) with a condition the line
does not show (the CPU in STOP, a coordination flag still set), with the seat's T_RES running
out early or late within the tolerance of a timer, and with the other reading of each of the
manual's open points the fuzzer knows. :meth:`Replays.command_problem` says why no CP 341 sends
a command: a responder with every block number and the largest areas refuses its header.
"""

from __future__ import annotations

import copy
from dataclasses import replace
from typing import TYPE_CHECKING, Any, Callable

from ptpcert.model.codes import Code
from ptpcert.procedures.rk512.analysis.probe import Probe, generous
from ptpcert.procedures.rk512.model import codec as K
from ptpcert.procedures.rk512.model.readings import RK512_READINGS

if TYPE_CHECKING:
    from ptpcert.procedures.rk512.analysis.frames import SeatFrames

#: the reading alternatives, each with what it says
_READING_WORDS = {
    "AMB-01": "a responder accepts 'C' for counters", "AMB-03": "a responder accepts type 'X' in a SEND",
    "AMB-10": "a too-short frame is handled the other way", "AMB-13": "byte 2 of a command is checked",
    "AMB-14": "byte 5 of a byte or cell address is ignored", "AMB-16": "a SEND may be split into any chunks",
    "AMB-17": "T_RES runs from the hand-over of the command",
    "AMB-18": "the other reading of an aborted partner request",
    "AMB-20": "a CP 341's limits on FETCH of timers, counters and DX", "AMB-22": "the other CPU number readings",
    "AMB-23": "byte 9 FFh needs byte 10's low nibble Fh", "AMB-25": "a request beyond its area is an area error",
    "AMB-31": "responses go before commands", "AMB-32": "an early response ends the request",
    "AMB-33": "an error response with data reports its REATEL", "N1": "a bad byte 1 is answered with FFh",
    "N3": "a continuation's wrong count is 16#060B", "N4": "SEND data are written at the end",
    "N5": "LEN over 1024 is 16#1E41", "N6": "DB 0 is 16#0301", "N7": "a pipelined command does not abort",
}


class Replays:
    """The alternatives of the frame layer, and the header check of a command, for
    :class:`~ptpcert.procedures.rk512.analysis.analyzer.Rk512Analyzer` (it brings ``rk``,
    ``late_abs``, ``_checker`` and ``_alts``)."""

    # -- the model's decisions, reused ----------------------------------------------------
    def command_problem(self, seat: str, frame: bytes) -> tuple[int, str] | None:
        """Why no CP 341 sends the command ``frame``: (the STATUS a responder raises, what is
        wrong), or None. Byte 2 is checked first (Table 2-1: 00h), then the model's responder,
        with every block number and the largest areas, judges the header: what it refuses is
        the header's fault, not the partner's memory."""
        if frame[1:2] != b"\x00":
            return (Code.CMD_BYTE1_INVALID, f"byte 2 is {frame[1]:02X}h, not 00h")
        probe = self._checker.get(seat)
        if probe is None:
            probe = self._checker[seat] = Probe(generous(self.rk[seat]), name="checker")
        probe = copy.deepcopy(probe)
        probe.frame_received(0.0, bytes(frame))
        e = probe.first("P")
        code = next((c for _, c in probe.codes), None)
        if e is None or len(e.frame) < 4 or e.frame[3] == 0 or code is None:
            return None
        return (code, f"a responder with every area refuses its header with REATEL {e.frame[3]:02X}h")

    def passive_alternatives(self, frames: SeatFrames, log: list[tuple]):
        """The passive side replayed with each alternative: (description, kind, reading, probe)."""
        params = frames.params
        first = next((x[2] for x in log if x[0] == "rx"), b"")
        out = []
        conditions = [("with the CPU in STOP (§7.3; Table 8-1 16#060D)", "stop")]
        if len(first) >= K.HEADER_LEN and first[8] != K.NO_FLAG:
            conditions.append((f"with coordination flag {first[8]}.{first[9] & 15} still set by the "
                               "application (§6.3.2 'Using interprocessor communication flags')", "lock"))
        for name, cond in conditions:
            out.append((name, "condition", "", self._replay(params, RK512_READINGS, None, log, cond)))
        return out + self._timings_and_readings(params, lambda r, tr: self._replay(params, r, tr, log, None))

    def active_alternatives(self, frames: SeatFrames, log: list[tuple], t: float):
        """The active side replayed up to ``t`` with each alternative: (description, kind,
        reading, probe)."""
        params = frames.params
        return self._timings_and_readings(params, lambda r, tr: self._replay_active(params, r, tr, log, t))

    def _timings_and_readings(self, params, replay: Callable[[Any, float | None], Probe]) -> list:
        """The alternatives of either side but the conditions: the seat's T_RES running out
        early or late within the tolerance of a timer, and the other reading of each open
        point, each replayed by ``replay(readings, t_res)`` (None: the seat's T_RES):
        (description, kind, reading, probe)."""
        out = []
        t_res = params.t_res
        for factor, words in ((0.95, "early"), (1.25, "late")):
            tr = factor * t_res + (self.late_abs if factor > 1 else 0.0)
            out.append((f"with its T_RES running out {1000 * abs(tr - t_res):.0f} ms {words} (within the "
                        "tolerance of a timer)", "timing", "", replay(RK512_READINGS, tr)))
        for name, change in self._alternatives():
            out.append((f"with the other reading of the manual's open point {name} "
                        f"({_READING_WORDS.get(name, 'see ptpcert.procedures.rk512.model.readings')})", "reading", name,
                        replay(replace(RK512_READINGS, **change), None)))
        return out

    @staticmethod
    def _replay_active(params, readings, t_res, log, t: float) -> Probe:
        p = Probe(params, readings, t_res=t_res)
        for kind, at, frame, *handed in log:
            if kind == "cmd":
                if len(frame) >= K.HEADER_LEN and frame[2] in K.COMMAND_LETTERS and K.AREA_BY_CODE.get(frame[3]):
                    p.install(at, frame, *handed)
            elif kind == "rsp":
                p.at(at)
                p.frame_received(at, frame)
            elif kind == "cont":
                e = p.take("A")
                if e is not None:
                    p.continued(at, e, frame, *handed)
        p.at(t)
        p.codes = []
        return p

    def _alternatives(self) -> list:
        if self._alts is None:
            from ptpcert.procedures.rk512.fuzz import ALTERNATIVE_READINGS
            self._alts = list(ALTERNATIVE_READINGS)
        return self._alts

    @staticmethod
    def _replay(params, readings, t_res, log, condition) -> Probe:
        p = Probe(params, readings, t_res=t_res)
        last = max((i for i, x in enumerate(log) if x[0] == "rx"), default=-1)
        for i, x in enumerate(log):
            if x[0] == "rx":
                _, t, frame = x
                p.at(t)
                if condition == "stop" and i == last:
                    p.memory.running = False      # the CPU went to STOP before this frame
                if condition == "lock" and len(frame) >= K.HEADER_LEN and frame[0] == K.FIRST and frame[8] != K.NO_FLAG \
                        and p.memory.flag_exists(frame[8], frame[9] & 15):
                    p.memory.set_flag(frame[8], frame[9] & 15, p.readings.amb07_locked_value)
                p.received(t, frame)
            elif x[0] == "ack":
                e = p.take("P")
                if e is not None:
                    p.acked(x[1], e)
            elif x[0] == "fail":
                e = p.take("P")
                if e is not None:
                    p.response_failed(x[1], e)
        p.codes = []
        return p
