"""The probes of RK 512's line analysis: the model's own RK 512 layer, fed what the line shows.

Each seat's frame layer (:mod:`~ptpcert.procedures.rk512.analysis.frames`) follows the seat
with two :class:`Probe` objects. A probe is the model's RK 512 layer
(:class:`~ptpcert.procedures.rk512.model.core.Rk512Core`, so the analysis and the model cannot
disagree) whose frames are collected as what the seat owes (:class:`Expect`) instead of going
to a link:

* the *passive* probe (Fig. 2-19) is fed the partner's commands and continuation commands:
  the response it makes is what the seat owes, due within the partner's T_RES
  (Figs. 2-18/2-19);
* the *active* probe (Fig. 2-18) takes each command of the seat as a job of the seat
  (:meth:`Probe.install`) and is fed the partner's responses: after a response with REATEL
  00h and data still to go, the seat owes the continuation command (its bytes 3/4 those of
  the first frame, its data count the next chunk, §2.2.3); after an error response it sends
  none.

The memory behind a seat is not on the line: a probe's memory knows which areas exist and how
large they are (the profile's [rk512] table), never what they hold; :func:`generous` gives a
responder with every area, which refuses only what is wrong with a command's header.
:func:`to_passive` says which of the two probes a frame the seat received goes to. This module
is the bottom of the package: it imports no other module of it.
"""

from __future__ import annotations

import copy
from dataclasses import dataclass
from math import inf
from types import SimpleNamespace
from typing import Any

from ptpcert.analysis.interface import EPS
from ptpcert.procedures.rk512.model import codec as K
from ptpcert.procedures.rk512.model.core import Job, Rk512Core
from ptpcert.procedures.rk512.model.memory import Memory
from ptpcert.procedures.rk512.model.params import Rk512Params
from ptpcert.procedures.rk512.model.readings import RK512_READINGS
from ptpcert.procedures.rk512.model.table import AInput, AState, PInput, PState

_WAITING = (AState.WAIT_RESPONSE, AState.WAIT_CONTINUATION_RESPONSE)


# ------------------------------------------------------------------ memory geometry


class _Sized:
    """An area of ``n`` bytes whose contents are not known: reads give zeros, writes vanish
    (the analysis never judges data values)."""

    __slots__ = ("n",)

    def __init__(self, n: int):
        self.n = n

    def __len__(self) -> int:
        return self.n

    def __getitem__(self, s: slice) -> bytes:
        return bytes(len(range(*s.indices(self.n))))

    def __setitem__(self, s: slice, data: bytes) -> None:
        pass


class _Geometry(Memory):
    """The memory of a seat as the line sees it: which areas exist and how large they are
    (its profile's [rk512] table), the coordination flags (the application may clear them at
    any time: every first command finds its flag clear), the CPU running."""

    def __init__(self, params: Rk512Params):
        self.params = p = params
        self._db = _Sized(p.db_bytes)
        self._ranges = {K.Area.DB: p.db_range, K.Area.DX: p.dx_range}
        nb, nc = p.byte_area_bytes, 2 * p.cell_area_cells
        self.db, self.dx = {}, {}
        self.areas = {K.Area.E: _Sized(nb), K.Area.A: _Sized(nb), K.Area.M: bytearray(nb),
                      K.Area.T: _Sized(nc), K.Area.Z: _Sized(nc)}
        self.running = True

    def buffer(self, area, number: int = 0):
        if area is K.Area.DB or area is K.Area.DX:
            rng = self._ranges[area]
            return self._db if rng and rng[0] <= number <= rng[1] else None
        return self.areas[area]


def generous(params: Rk512Params) -> Rk512Params:
    """The parameters of a responder with every block number and the largest areas: what it refuses, no CP 341
    requests (the header itself is wrong)."""
    return params.with_(db_range=(1, 255), dx_range=(1, 255), db_bytes=65536, byte_area_bytes=65536,
                        cell_area_cells=32768)


# ------------------------------------------------------------------ the probes


@dataclass
class Expect:
    """A frame the seat owes: ``origin`` "P" (a response) or "A" (a continuation command),
    ``owner`` the request it belongs to, ``since`` when it became due, ``code`` the STATUS
    event it reports."""

    frame: bytes
    origin: str
    owner: Any
    since: float
    code: int | None
    reported: bool = False
    partial_judged: bool = False


class Probe(Rk512Core):
    """One side of the seat's RK 512 layer, fed what the line shows; what it would send is
    collected in :attr:`expect` instead of going to a link."""

    def __init__(self, params: Rk512Params, readings=RK512_READINGS, *, t_res: float | None = None,
                 name: str = "probe"):
        super().__init__(params, readings, memory=_Geometry(params), name=name)
        if t_res is not None:
            self._t_res = t_res
        self.frame_events = False
        self.powered = True
        self.expect: list[Expect] = []
        self.codes: list[tuple[float, int]] = []

    def _queue(self, frame, origin, owner, detail=""):
        # the event the frame reports: its row's, or the one a check raised just before it
        row = self._row
        code = row.code if row is not None else None
        if code is None and self.codes and self.codes[-1][0] >= self.now - EPS:
            code = self.codes[-1][1]
        self.expect.append(Expect(bytes(frame), origin, owner, self.now, code))

    def _status(self, code, side, final=False):
        self.codes.append((self.now, int(code)))

    def take(self, kind: str) -> Expect | None:
        for i, e in enumerate(self.expect):
            if e.origin == kind:
                return self.expect.pop(i)
        return None

    def first(self, kind: str) -> Expect | None:
        return next((e for e in self.expect if e.origin == kind), None)

    def __deepcopy__(self, memo):
        # the parameters and readings are frozen: shared
        memo[id(self.params)] = self.params
        memo[id(self.readings)] = self.readings
        new = self.__class__.__new__(self.__class__)
        memo[id(self)] = new
        for k, v in self.__dict__.items():
            setattr(new, k, copy.deepcopy(v, memo))
        return new

    def received(self, t: float, frame: bytes) -> None:
        """The seat took ``frame`` at ``t``: what it makes the seat owe is due from ``t`` (not
        from the instant the probe's clock shows)."""
        self.frame_received(t, frame)
        for e in self.expect:
            if e.since >= t - EPS:
                e.since = t

    def at(self, t: float, inclusive: bool = False) -> None:
        """Run the timers due before ``t`` (inputs of an instant go before its deadlines), or
        by ``t`` (``inclusive``)."""
        limit = t + EPS if inclusive else t - 3 * EPS
        if self.own_deadline() <= limit:
            self.handle_timer(limit)
        if t > self.now:
            self.now = t

    # -- the passive side -----------------------------------------------------------------
    def acked(self, t: float, e: Expect) -> None:
        """The seat's response ``e`` was accepted by the partner."""
        self.at(t)
        if e.owner is not None and e.owner is self.open and self.p_state is PState.SEND_RESPONSE:
            self._passive(PInput.RESPONSE_SENT)

    def response_failed(self, t: float, e: Expect) -> None:
        self.at(t)
        if e.owner is not None and e.owner is self.open and self.p_state is PState.SEND_RESPONSE:
            self._passive(PInput.RESPONSE_NOT_SENT)

    # -- the active side ------------------------------------------------------------------
    def install(self, t: float, frame: bytes, handed: float | None = None) -> None:
        """The seat's first command frame ``frame`` (handed to the link at ``handed``) was
        accepted at ``t``: its job, awaiting the response."""
        self.at(t)
        h = K.decode_header(frame)
        fetch = h.is_fetch
        frames = [bytes(frame)]
        if fetch:
            frames += [h.continuation] * (len(K.chunk_sizes(h.nbytes)) - 1)
        else:
            # the continuations that carry what the first frame did not (however many it did)
            rest = h.nbytes - (len(frame) - K.HEADER_LEN)
            frames += [h.continuation + bytes(n) for n in K.chunk_sizes(rest)] if rest > 0 else []
        req = SimpleNamespace(label=K.describe(frame), length=h.nbytes)
        job = Job(req, h, frames, fetch)
        self.job = job
        self.a_state = AState.SEND_COMMAND
        self._active(AInput.COMMAND_SENT)
        self._handed(t if handed is None else handed)

    def _handed(self, at: float) -> None:
        """T_RES from the hand-over of the frame, where that reading is taken (AMB-17)."""
        if self._tres_at_handover and self.job is not None:
            self._t_res_a = at + self._t_res

    def drop_job(self) -> None:
        self.job = None
        self._t_res_a = inf
        self.a_state = AState.IDLE
        self.expect = [e for e in self.expect if e.origin != "A"]

    def continued(self, t: float, e: Expect, frame: bytes, handed: float | None = None) -> None:
        """The seat's continuation command was accepted."""
        self.at(t)
        job = self.job
        if job is not None and self.a_state is AState.SEND_CONTINUATION:
            if job.k < len(job.frames):
                job.frames[job.k] = bytes(frame)
            self._active(AInput.COMMAND_SENT)
            self._handed(t if handed is None else handed)

    def continuation_failed(self, t: float) -> None:
        self.at(t)
        if self.a_state is AState.SEND_CONTINUATION:
            self._active(AInput.COMMAND_NOT_SENT)

    @property
    def resting(self) -> bool:
        return (self.a_state is AState.IDLE and self.p_state is PState.IDLE and self.job is None
                and self.open is None and not self.expect)


def to_passive(frame: bytes, active: Probe) -> bool:
    """Does a frame the seat received go to its passive side (a command)? By byte 3, as the
    model classifies (§2.2.3); a frame too short to tell is a response when one is awaited."""
    if len(frame) >= 3:
        return bool(frame[2])
    return active.a_state not in _WAITING
