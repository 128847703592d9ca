"""The RK 512 frames of a seat judged against what its probes say the seat owes.

The part of :class:`~ptpcert.procedures.rk512.analysis.frames.SeatFrames` that judges
(:class:`FrameJudging`, mixed into it). A seat's response must be the one its passive probe
makes (:func:`response_problem`): first or continuation response (byte 1, Table 2-2), bytes 2
and 3 00h, the REATEL the model's header checks give (Table 8-3) and as many data bytes (a
FETCH response carries the chunk asked for, §2.2.3; every other response none). The data
values are not judged: the memory behind a seat is not on the line. A response nobody asked
for, or a missing one, is a finding. A continuation command must carry the header and the
chunk the active probe gives; a command must be one a CP 341 sends (Table 2-1, its header
checked by a responder with room for every address), and a seat has at most one request of
its own open (nesting depth 1, §2.2.3 "Quasi-full-duplex").

Before a difference stands, the alternatives of
:class:`~ptpcert.procedures.rk512.analysis.replays.Replays` are tried: a REATEL that a condition
of the seat the line does not show explains (the CPU in STOP: 2Ah, §7.3; a coordination flag
still set: 32h, §6.3.2) is conforming; one that the other reading of an open point of the
manual (AMB-xx, :class:`~ptpcert.procedures.rk512.model.readings.Rk512Readings`) or the seat's
T_RES at the edge of its tolerance explains is an informational finding, never a fail.
"""

from __future__ import annotations

from ptpcert import results as R
from ptpcert.analysis import Finding
from ptpcert.model.codes import Code
from ptpcert.procedures.rk512.analysis.probe import Expect
from ptpcert.procedures.rk512.model import codec as K
from ptpcert.procedures.rk512.model.table import AState

#: what a response carries, for people
_RESPONSE_RULE = ("RK 512 answers every command it accepted with exactly one response: byte 1 00h (FFh for a "
                  "continuation command), bytes 2 and 3 00h, byte 4 the error number (REATEL) of the responder's "
                  "checks, and data only in a FETCH response with REATEL 00h, the chunk asked for")
_RESPONSE_REF = "§2.2.3 'Response message frame'; Table 2-2; Fig. 2-19; Table 8-3"
_UNASKED = ("a response answers a command of the partner that is still unanswered: responses are never "
            "themselves answered, and a station sends none it does not owe",
            "§2.2.3 'Response message frame'; Figs. 2-13 to 2-16, 2-19; Table 8-1 16#0A01")
_MISSING = ("the responder answers a command within the requester's response monitoring time T_RES (the "
            "requester then gives up with 16#0A05)",
            "§2.2.3 'Response message frame'; Figs. 2-18, 2-19 'T > T_RES'; Table 8-1 16#0A05")
_CONT_MISSING = ("after a response with REATEL 00h to a frame of its request, the requester sends the next "
                 "continuation command within the responder's T_RES while data are left (the responder aborts "
                 "after T_RES)",
                 "§2.2.3 'Continuation frames'; Fig. 2-18 'send continuation command frame'; Fig. 2-19 'T > T_RES'")
_CONT_UNASKED = ("a continuation command follows only the response with REATEL 00h to the previous frame of "
                 "the same request, while data are left (nesting depth 1)",
                 "§2.2.3 'Quasi-full-duplex', 'Continuation frames'; Fig. 2-18; Table 8-1 16#060E")
_CONT_RULE = ("a continuation command carries the 4-byte header FFh 00h with bytes 3 and 4 of the first "
              "command frame, and the next chunk of the data: 128 bytes, the rest in the last frame (a FETCH "
              "continuation no data)",
              "§2.2.3 'Continuation frames', Table 2-1; Figs. 2-14, 2-16; Table 8-1 16#0603, 16#0605, 16#0611")
_DEPTH = ("a station has at most one request of its own open: it sends its next command only after the "
          "response to the last frame of the previous request (nesting depth 1)",
          "§2.2.3 'Quasi-full-duplex'; §6.3.2 'Parallel processing of requests'; Fig. 2-18")
#: the rule a command breaks that no CP 341 sends (the frame layer cites it for a frame whose end
#: the line does not show)
COMMAND_RULE = ("a command frame is one a CP 341 sends for a valid request: byte 1 00h, byte 2 00h, the "
                "command letter and data type of Table 2-1, a length of 1 to 1024 bytes, a valid flag and CPU "
                "number, and (SEND) the first 128 data bytes, the rest in continuation frames",
                "§2.2.3 Table 2-1, Fig. 2-13; §6.3.2 Tables 6-4 to 6-8")
#: the rules above by the names the RK 512 fuzz kit gives them (a finding of the fuzzer and
#: of ``analyze`` name one rule)
RESPONSE_RULE, UNASKED_RULE, CONTINUATION_RULE = (_RESPONSE_RULE, _RESPONSE_REF), _UNASKED, _CONT_RULE
_FRAME_ID = ("byte 1 of an RK 512 frame is 00h (first frame) or FFh (continuation frame)",
             "§2.2.3 Tables 2-1, 2-2; Table 8-1 16#0601, 16#0A02")


#: the ids of the RK 512 catalogue (``ptpcert rules --procedure RK512``) each rule above stands
#: for, by its sentence; a response's problem by the reference :func:`response_problem` gives it
RULE_IDS: dict[str, tuple[str, ...]] = {
    _UNASKED[0]: ("RK512.RESP.NOT-ANSWERED", "RK512.RESP.ONE-PER-COMMAND"),
    _MISSING[0]: ("RK512.RESP.ONE-PER-COMMAND", "RK512.TRES.RESPONSE-IN-TIME"),
    _CONT_MISSING[0]: ("RK512.SEG.SEND-FRAMES", "RK512.SEG.FETCH-FRAMES"),
    _CONT_UNASKED[0]: ("RK512.SEG.NEXT-AFTER-RESPONSE", "RK512.SEG.ERROR-ENDS-REQUEST"),
    _CONT_RULE[0]: ("RK512.SEG.SEND-FRAMES", "RK512.SEG.FETCH-FRAMES", "RK512.SEG.CHUNK-128"),
    _DEPTH[0]: ("RK512.QFD.NESTING-DEPTH-1",),
    COMMAND_RULE[0]: ("RK512.CMD.HEADER", "RK512.TYPE.LETTERS", "RK512.CMD.FLAG-AND-CPU"),
    _FRAME_ID[0]: ("RK512.CMD.HEADER",),
}
_PROBLEM_IDS: dict[str, tuple[str, ...]] = {
    "Table 2-2; Table 8-1 16#0610": ("RK512.RESP.LAYOUT",),
    "§2.2.3 Table 2-2; Table 8-1 16#0A01, 16#0A02": ("RK512.RESP.MIRRORS-COMMAND",),
    "§2.2.3 Table 2-2": ("RK512.RESP.LAYOUT",),
    "§8.4 Table 8-3; Table 8-1 16#090E": ("RK512.RESP.REATEL-VALUES",),
    "§2.2.3 'Response message frame'; Fig. 2-19; §8.4 Table 8-3": ("RK512.RESP.REATEL-VALUES",
                                                                 "RK512.STATUS.RESPONDER-EVENTS"),
    "§2.2.3 'Receiving data'; Table 8-1 16#0A03, 16#0A04": ("RK512.RESP.ERROR-NO-DATA",),
    "§2.2.3 'SEND message frame'; Table 8-1 16#0A04": ("RK512.RESP.SEND-NO-DATA",),
    "§2.2.3 'FETCH message frame', Figs. 2-15, 2-16; Table 8-1 16#0A03": ("RK512.RESP.FETCH-DATA",),
}


def rule_ids(rule: tuple[str, str]) -> tuple[str, ...]:
    """The catalogue's ids for a finding's (sentence, reference)."""
    if rule[0] == _RESPONSE_RULE:
        return _PROBLEM_IDS.get(rule[1], ("RK512.RESP.LAYOUT",))
    return RULE_IDS.get(rule[0], ())


class FrameJudging:
    """The judgement of a seat's RK 512 frames, for
    :class:`~ptpcert.procedures.rk512.analysis.frames.SeatFrames` (it brings ``kit``, ``seat``,
    ``partner``, the probes ``passive`` and ``active``, their logs ``plog`` and ``alog``,
    ``overdue`` and :meth:`_due`)."""

    def _finding(self, run, t: float, grade: str, kind: str, rule: tuple[str, str], message: str, *,
                 expected: str = "", observed: str = "", codes: tuple[int, ...] = (),
                 readings: tuple[str, ...] = ()) -> None:
        run.findings.append(Finding(self.seat, t, grade, kind, rule[0], rule[1], message, expected=expected,
                                    observed=observed, codes=codes, readings=readings, rules=rule_ids(rule)))

    def _missing(self, run, e: Expect) -> None:
        due = self._due(e)
        t_res = 1000 * self.partner.t_res
        if e.origin == "P":
            what = K.describe(e.frame)
            self._finding(run, due, R.FAIL, "missing", _MISSING,
                          f"RK 512 {what} missing: the partner's command was accepted "
                          f"{1000 * (due - e.since):.0f} ms ago and its T_RES is {t_res:g} ms: "
                          f"{_MISSING[0]} ({_MISSING[1]})",
                          expected=f"{what} within {t_res:g} ms", observed="nothing",
                          codes=(e.code,) if e.code else ())
        else:
            what = K.describe(e.frame)
            self._finding(run, due, R.FAIL, "missing", _CONT_MISSING,
                          f"RK 512 {what} missing: {_CONT_MISSING[0]} ({_CONT_MISSING[1]})",
                          expected=f"{what} within {t_res:g} ms", observed="nothing")

    def _came_late(self, origin: str) -> bool:
        """Is the seat's frame one it owed (``origin`` as in :class:`Expect`) that was reported
        missing already? Then it came late, and is off the list."""
        late = next((x for x in self.overdue if x.origin == origin), None)
        if late is not None:
            self.overdue.remove(late)
            return True
        return False

    def _response(self, run, at: float, t: float, frame: bytes, anchored: bool) -> None:
        p = self.passive
        e = p.first("P")
        if e is None:
            if self._came_late("P"):
                return          # the late response, reported missing already
            if anchored:
                self._finding(run, at, R.FAIL, "unexpected", _UNASKED,
                              f"sent RK 512 {K.describe(frame)} where it owes no response: {_UNASKED[0]} "
                              f"({_UNASKED[1]})",
                              expected="no RK 512 frame", observed=K.describe(frame),
                              codes=(Code.RESPONSE_OUT_OF_SEQUENCE,))
            return
        problem = None if e.partial_judged else response_problem(frame, e.frame)
        if problem is not None:
            self._alternatives(run, at, t, frame, e, problem)   # may follow the seat with another probe
            p = self.passive
            e = p.first("P")
            if e is None:
                return
        p.take("P")
        p.acked(t, e)
        self.plog.append(("ack", t))

    def _alternatives(self, run, at: float, t: float, frame: bytes, e: Expect, problem: tuple[str, str],
                      partial: bool = False) -> None:
        """The seat's response differs from the model's: a condition the line does not show,
        another reading of an open point, or the seat's T_RES at the edge of its tolerance
        may explain it; else the difference stands."""
        for name, kind, reading, probe in self.kit.passive_alternatives(self, self.plog):
            alt = probe.first("P")
            if alt is None or response_problem(frame, alt.frame, partial) is not None:
                continue
            if partial:
                alt.partial_judged = True
            # follow the seat with the alternative from here on
            self.passive, self.pvariant = probe, (name, kind)
            text = (f"sent RK 512 {K.describe(frame)} where the model sends {K.describe(e.frame)}: {problem[0]}")
            if kind == "condition":
                run.notes.append((at, f"{text} - {name}, which the line does not show, explains it"))
            else:
                self._finding(run, at, R.INFORMATIONAL, "reading" if kind == "reading" else "timing",
                              (_RESPONSE_RULE, problem[1]),
                              f"{text} - but the model {name} follows the seat ({_RESPONSE_REF})",
                              expected=K.describe(e.frame), observed=K.describe(frame),
                              readings=(reading,) if reading else ())
            return
        codes = (e.code,) if e.code else ()
        partner_code = _partner_sees(frame, e.frame)
        self._finding(run, at, R.FAIL, "wrong", (_RESPONSE_RULE, problem[1]),
                      f"sent RK 512 {K.describe(frame)} where the model sends {K.describe(e.frame)}: {problem[0]} "
                      f"({problem[1]})" + (f"; the model's responder raises {Code(e.code).text}" if e.code else "")
                      + (f"; the partner raises {Code(partner_code).text}" if partner_code else ""),
                      expected=K.describe(e.frame), observed=K.describe(frame), codes=codes)

    def _continuation(self, run, at: float, t: float, frame: bytes, anchored: bool) -> None:
        a = self.active
        e = a.first("A")
        if e is None:
            if self._came_late("A"):
                return          # the late continuation, reported missing already
            text = f"sent RK 512 {K.describe(frame)} where no continuation is due"
            if anchored and not self._active_alternatives(run, at, t, frame, "continuation", text, _CONT_UNASKED):
                self._finding(run, at, R.FAIL, "unexpected", _CONT_UNASKED,
                              f"{text}: {_CONT_UNASKED[0]} ({_CONT_UNASKED[1]})",
                              expected="no continuation command", observed=K.describe(frame))
            if self.active.first("A") is None:
                return
            a = self.active
            e = a.first("A")
        problem = None
        if len(frame) < 4 or frame[:4] != e.frame[:4]:
            problem = (f"its header is {frame[:4].hex(' ').upper()}, not {e.frame[:4].hex(' ').upper()}",)
        elif len(frame) != len(e.frame):
            problem = (f"it carries {len(frame) - 4} data bytes, not {len(e.frame) - 4}",)
        if problem is not None:
            self._finding(run, at, R.FAIL, "wrong", _CONT_RULE,
                          f"sent RK 512 {K.describe(frame)} where the model sends {K.describe(e.frame)}: "
                          f"{problem[0]}: {_CONT_RULE[0]} ({_CONT_RULE[1]})",
                          expected=K.describe(e.frame), observed=K.describe(frame))
        a.take("A")
        a.continued(t, e, frame, at)
        self.alog.append(("cont", t, frame, at))

    def _active_alternatives(self, run, at: float, t: float, frame: bytes, what: str, text: str,
                             rule: tuple[str, str]) -> bool:
        """The seat's request went on (a continuation) or ended (a new command) where the
        model's did not: another reading of an open point, or the seat's T_RES at the edge of
        its tolerance, may explain it. True (and the seat followed with it) when one does."""
        for name, kind, reading, probe in self.kit.active_alternatives(self, self.alog, t):
            if what == "continuation":
                e = probe.first("A")
                if e is None or frame[:4] != e.frame[:4] or len(frame) != len(e.frame):
                    continue
            elif probe.job is not None or probe.a_state is not AState.IDLE:
                continue
            self.active = probe
            self._finding(run, at, R.INFORMATIONAL, "reading" if kind == "reading" else "timing", rule,
                          f"{text} - but the model {name} follows the seat ({rule[1]})",
                          observed=K.describe(frame), readings=(reading,) if reading else ())
            return True
        return False

    def _command(self, run, at: float, t: float, frame: bytes, anchored: bool) -> None:
        a = self.active
        if len(frame) < 1 or frame[0] != K.FIRST:
            if anchored:
                self._finding(run, at, R.FAIL, "wrong", _FRAME_ID,
                              f"sent RK 512 {K.describe(frame)}: {_FRAME_ID[0]} ({_FRAME_ID[1]})",
                              observed=K.describe(frame), codes=())
            return
        if a.job is not None or a.a_state is not AState.IDLE or a.expect:
            text = (f"sent RK 512 {K.describe(frame)} while its request "
                    f"{a.job.label if a.job is not None else ''} is still open")
            if anchored and not self._active_alternatives(run, at, t, frame, "command", text, _DEPTH):
                self._finding(run, at, R.FAIL, "unexpected", _DEPTH, f"{text}: {_DEPTH[0]} ({_DEPTH[1]})",
                              expected="no new command", observed=K.describe(frame))
            a = self.active
            a.drop_job()
        self.alog = [("cmd", t, frame, at)]
        bad = self.kit.command_problem(self.seat, frame)
        if bad is not None:
            code, why = bad
            self._finding(run, at, R.FAIL, "wrong", COMMAND_RULE,
                          f"sent RK 512 {K.describe(frame)}: {why}; a CP 341 responder refuses it with "
                          f"{Code(code).text}: {COMMAND_RULE[0]} ({COMMAND_RULE[1]})",
                          expected="a command of Table 2-1", observed=K.describe(frame))
        if len(frame) >= K.HEADER_LEN and frame[2] in K.COMMAND_LETTERS and K.AREA_BY_CODE.get(frame[3]) is not None:
            a.install(t, frame, at)


def response_problem(got: bytes, want: bytes, partial: bool = False) -> tuple[str, str] | None:
    """How the seat's response ``got`` differs from the model's ``want`` (data values aside):
    (what, the manual's reference), or None. ``partial``: only the beginning of the frame is
    on record (the recording, or the case, ended inside its block): what is there is judged."""
    if partial:
        if len(got) > len(want) and (len(got) > 4 or got[:4] != want[:4]):
            return response_problem(got, want)
        n = min(len(got), 4)
        got, want = got[:n] + want[n:4], want[:4]
        if got == want:
            return None
    if len(got) < 4:
        return (f"a response has 4 bytes at least, this one {len(got)}", "Table 2-2; Table 8-1 16#0610")
    if got[0] != want[0]:
        return (f"byte 1 is {got[0]:02X}h, not {want[0]:02X}h: a {'first' if want[0] == K.FIRST else 'continuation'} "
                f"command gets a {'first' if want[0] == K.FIRST else 'continuation'} response",
                "§2.2.3 Table 2-2; Table 8-1 16#0A01, 16#0A02")
    if got[1] or got[2]:
        return (f"bytes 2 and 3 are {got[1]:02X}h {got[2]:02X}h, not 00h 00h", "§2.2.3 Table 2-2")
    if got[3] != want[3]:
        if got[3] and got[3] not in K.REATEL_STATUS:
            return (f"REATEL {got[3]:02X}h is no error number of Table 8-3 (the partner raises 16#090E); the "
                    f"model's checks give {want[3]:02X}h", "§8.4 Table 8-3; Table 8-1 16#090E")
        return (f"REATEL {got[3]:02X}h, the model's checks give {want[3]:02X}h"
                + (f" (which the requester reports as {K.status_for_reatel(want[3]).text})" if want[3] else ""),
                "§2.2.3 'Response message frame'; Fig. 2-19; §8.4 Table 8-3")
    if len(got) != len(want):
        if got[3]:
            return (f"an error response carries no data, this one {len(got) - 4} bytes",
                    "§2.2.3 'Receiving data'; Table 8-1 16#0A03, 16#0A04")
        if len(want) == 4:
            return (f"a response to a SEND carries no data, this one {len(got) - 4} bytes",
                    "§2.2.3 'SEND message frame'; Table 8-1 16#0A04")
        return (f"it carries {len(got) - 4} data bytes, the FETCH asked for {len(want) - 4} in this frame",
                "§2.2.3 'FETCH message frame', Figs. 2-15, 2-16; Table 8-1 16#0A03")
    return None


def _partner_sees(got: bytes, want: bytes) -> int | None:
    """What a CP 341 requester raises on the seat's response ``got`` where ``want`` was due."""
    if len(got) < 4:
        return Code.FRAME_TOO_SHORT
    if got[0] not in (K.FIRST, K.CONTINUATION):
        return Code.RESPONSE_STRUCTURE
    if got[0] != want[0] or got[2]:
        return Code.RESPONSE_OUT_OF_SEQUENCE
    if got[3]:
        return K.status_for_reatel(got[3])
    if len(got) != len(want):
        return Code.RESPONSE_DATA_LENGTH if len(want) > 4 else Code.RESPONSE_TO_SEND_WITH_DATA
    return None
