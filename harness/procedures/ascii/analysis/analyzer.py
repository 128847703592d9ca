"""The ASCII analyzer: what the ASCII driver brings to line analysis.

:class:`AsciiAnalyzer` is the procedure's
:class:`~ptpcert.analysis.interface.ProcedureAnalyzer`: each judged seat is followed by the
reference model of the ASCII driver (§2.2.4), fed the other seat's characters. The analyzer
holds the timing (how long a quiet line must be before both stations rest, the longest pause
inside a frame, the pause between frames), builds the model station of each seat with what
the analysis knows of its application (:mod:`~ptpcert.procedures.ascii.analysis.host`), names
the alternatives to try before a difference stands (an application that reads each frame at
once, send jobs of any length under the fixed-length criterion, XOFF repeated, the other
readings of the manual's open points, the other seat's characters moved within the timing
resolution) and describes a seat's characters as the other seat's receiver delimits them
("frame 41 42 <ETX> (3 bytes, end character)"). What the seat's characters reveal comes from
:class:`~ptpcert.procedures.ascii.analysis.events.LocalEvents`; why the model sends each
character, and what a character breaks, from
:class:`~ptpcert.procedures.ascii.analysis.causes.Causes`.
"""

from __future__ import annotations

from dataclasses import replace
from typing import Any

from ptpcert.analysis import OTHER, QUANTUM, SEATS, ProcedureAnalyzer, Variant, resolution_variants
from ptpcert.procedures.ascii.analysis.causes import Causes
from ptpcert.procedures.ascii.analysis.events import LocalEvents
from ptpcert.procedures.ascii.analysis.host import DEFAULT, AnalysisReadings, AsciiAnalysisHost
from ptpcert.procedures.ascii.model import AsciiStation
from ptpcert.procedures.ascii.model.codec import char_name, split_frames
from ptpcert.procedures.ascii.model.readings import READINGS, AsciiReadings
from ptpcert.procedures.ascii.model.table import FcState, TxState

#: the readings of the open points the alternatives take, in words
_READING_WORDS = {
    "Q4": "a gap of exactly the CDT ends a frame (no grace of one character time)",
    "Q5": "the pause between sent frames is exactly the CDT",
    "Q6": "variant 1 without an end character refuses the job, or cuts at end character 1 alone",
    "Q14": "XOFF one frame before the buffered frames reach the parameter",
    "Q15": "XON after every read, or not after a discard",
    "Q16": "a received XON/XOFF restarts the CDT, or an XOFF while idle does not hold the next frame",
    "d_hold": "the CDT of a frame runs on while the station holds its partner",
    "d_break": "a BREAK also ends the running send job",
}


class AsciiAnalyzer(LocalEvents, Causes, ProcedureAnalyzer):
    """Line analysis of a link between two ASCII drivers (see the module docstring). ``late_ms``
    is the tolerance of the timing windows (see :mod:`~ptpcert.procedures.ascii.analysis.causes`)."""

    reference = "§2.2.4; Figs. 2-20 to 2-23; Tables 2-7 to 2-10"

    def __init__(self, procedure: Any, params: dict[str, Any], apps: dict[str, str] | None = None,
                 late_ms: float = 50.0):
        super().__init__(procedure, params, apps)
        self.late_abs = late_ms / 1000.0
        ps = list(self.params.values())
        # the longest timer after which a station that has stopped sending and receiving is at
        # rest: the CDT (a frame ends, or is discarded) and the pause after it. (The wait
        # time for XON is left out: a stopped sender that is followed afresh after a quiet
        # line sends the rest of its frame as a frame of its own, which the model accepts.)
        longest = max(p.cdt + p.char_time for p in ps)
        self._rest = 1.25 * longest + self.late_abs + 4 * max(self.char(s) for s in SEATS)
        self._unsendable: dict[tuple[str, int], str] = {}
        self._variants: list[Variant] | None = None
        flow = [p for p in ps if p.flow_control == "xon_xoff"]
        self._names: dict[int, str] = {}
        for p in flow:
            self._names.setdefault(p.xon, "XON")
            self._names.setdefault(p.xoff, "XOFF")

    # -- timing ---------------------------------------------------------------------------
    def rest_gap(self) -> float:
        return self._rest

    def _pause(self, p, readings: AsciiReadings = READINGS) -> float:
        return p.cdt + readings.q5_send_pause_extra_chars * p.char_time

    @staticmethod
    def _gap(p, q) -> float:
        """The longest pause inside a frame (and before the first character after the
        partner's XON): half the shorter CDT. A driver sends a frame back to back (it sends
        nothing before it has all of the job's data); a pause of half the CDT is where a
        receiver's timer may begin to take it for the end of the frame (the CDT runs again
        from an XON). Of two CDTs the shorter: a CP 341 partner is usually set as the station
        itself, and a tester's CDT may be a mere watchdog. A longer pause ends the job: what
        follows is another one (held back by the pause between frames where one is due)."""
        return 0.5 * min(p.cdt, q.cdt)

    def early_wait(self, host: AsciiAnalysisHost) -> float:
        st = host.station
        c = st.params.char_time
        if st.tx_state is TxState.PAUSE:
            return c + 0.05 * self._pause(st.params, st.readings) + 3e-6
        return c + 3e-6

    def late_max(self, seat: str) -> float:
        p, q = self.params[seat], self.params[OTHER[seat]]
        return max(self._gap(p, q) + 2 * p.char_time, self.late_abs + 0.25 * self._pause(p))

    # -- stations -------------------------------------------------------------------------
    def _readings(self, readings: Any) -> AnalysisReadings:
        if readings is None:
            return DEFAULT
        if isinstance(readings, AsciiReadings):
            return AnalysisReadings(model=readings)
        return readings

    def _host(self, seat: str, readings: Any = None) -> AsciiAnalysisHost:
        r = self._readings(readings)
        st = AsciiStation(self.params[seat], r.model, name=seat, explain=True)
        return AsciiAnalysisHost(st, self.apps[seat] in ("echo", "echo-only"), r, own_jobs=self.apps[seat] != "echo-only")

    def fresh(self, seat: str, t: float, readings: Any = None) -> AsciiAnalysisHost:
        host = self._host(seat, readings)
        st = host.station
        st.power_on(t - 2 * self.char(seat) - 1e-6)
        st.pop_output()
        st.pop_events()
        st.tx_log.clear()
        return host

    def powered(self, seat: str, t: float) -> AsciiAnalysisHost:
        host = self._host(seat)
        host.station.power_on(t)
        return host

    def at_rest(self, host: AsciiAnalysisHost) -> bool:
        """Where a model afresh would go on as this one: nothing to send, nothing stored,
        nobody held. (The pause after its last frame is kept across a rest point in the run's
        memo: see :meth:`event` and :meth:`_request`.)"""
        st = host.station
        return st.idle and st.fc_state is FcState.OPEN and not st.partner_stopped and not st.frames_stored

    def entry_start(self, entry: Any) -> float:
        return entry.start

    def continues(self, prev: Any, entry: Any) -> bool:
        # the station logs what it sent as it is popped: a frame whose schedule moved comes
        # in several records with one explanation
        return prev.why is entry.why and prev.kind == entry.kind

    # -- alternatives -----------------------------------------------------------------------
    def variants(self, seat: str, resolution: float) -> list[Variant]:
        out = resolution_variants(resolution, "send jobs and reads")
        if resolution <= 0:
            # the capture formats keep whole microseconds: an XOFF and the character a station
            # would have begun next that met within one came in either order
            out.append(Variant("resolution", "with the other seat's characters 2 µs earlier (the capture's "
                                             "timestamps are whole microseconds)", shift=-2 * QUANTUM))
        if self._variants is None:
            kit = self.procedure.fuzz_kit()
            alts = list(kit.alternatives if kit is not None else ()) + [
                ("Q5", dict(q5_send_pause_extra_chars=0.0)),
                ("Q15", dict(q15_xon_only_after_xoff=False)),
            ]
            self._variants = [
                Variant("buffer", "with an application that reads each frame as soon as it is stored (the echo held "
                                  "back by the send side; the reads are not on the line)",
                        readings=replace(DEFAULT, a_reads_at_once=True), kind="buffer"),
                Variant("a_fixed_length_job_is_one_frame",
                        "with send jobs of any length under the fixed-length criterion",
                        readings=replace(DEFAULT, a_fixed_length_job_is_one_frame=False)),
                Variant("Q15", "with the other reading of the manual's open point Q15 (a station holding its "
                               "partner repeats its XOFF while the partner keeps sending)",
                        readings=replace(DEFAULT, a_xoff_repeated=True)),
            ] + [
                Variant(name, f"with the other reading of the manual's open point {name} "
                              f"({_READING_WORDS.get(name, 'see ptpcert.procedures.ascii.model.readings')})",
                        readings=replace(DEFAULT, model=replace(READINGS, **change)))
                for name, change in alts]
        return out + self._variants

    # -- reports --------------------------------------------------------------------------
    def describe(self, seat: str, its: list) -> str:
        """A seat's characters as the other seat's receiver delimits them, e.g. "frame 41 42 <ETX>
        (3 bytes, end character)" (see :meth:`label`)."""
        rx = self.params[OTHER[seat]]
        parts: list[str] = []
        timed: list[tuple[float, int]] = []

        def flush() -> None:
            for piece in split_frames(timed, rx):
                parts.append(self._piece(piece, rx))
            timed.clear()

        for it in its:
            if it.kind == "byte":
                timed.append((it.start, it.value))
            else:
                flush()
                parts.append("BREAK" if it.kind == "break" else f"{it.value:02X}(error)")
        flush()
        return " ".join(parts)

    def _piece(self, piece, rx) -> str:
        if piece.kind in ("xon", "xoff"):
            return piece.kind.upper()
        body = piece.data[:len(piece.data) - piece.end_len]
        shown = " ".join(f"{x:02X}" for x in body[:8]) + (" ..." if len(body) > 8 else "")
        if piece.end_len:
            shown = (shown + " " if shown else "") + " ".join(f"<{char_name(x)}>" for x in piece.data[len(body):])
        n = len(piece.data)
        if piece.kind == "fragment":
            return f"fragment {shown} ({n} bytes, no end)"
        how = {"cdt": "ended by the CDT", "end_chars": "end character",
               "fixed_length": "fixed length"}[rx.end_criterion]
        return f"frame {shown} ({n} bytes, {how})"
