"""The local events a 3964/3964R seat's bytes reveal, for line analysis.

The part of :class:`~ptpcert.procedures.p3964.analysis.analyzer.P3964Analyzer` that reads the
line (:class:`LocalEvents`, mixed into it). Which local events the line reveals (what the
model cannot predict, so the seat's bytes say when it happened):

* an STX from a station without a send job starts one: its application handed over a block
  (Fig. 2-10 "send request"). The block is read ahead from the line: the bytes the station
  sends after the partner's DLE, up to DLE ETX, with each doubled DLE taken once. The model
  then sends that block its own way, so a block framed wrongly (DLE not doubled, a wrong
  BCC) differs from the model's;
* a receive buffer becomes free (Fig. 2-11 "buffer free"): the analysis cannot see the
  application's buffer, so it takes it as busy until the station's DLE shows it free. A DLE
  any time before T_NAKTIM is conforming; no DLE and no NAK after T_NAKTIM is not. A buffer
  seen free may be busy again at a later STX: a station that then answers late, or with NAK
  after T_NAKTIM, is an informational finding of kind "buffer" (the alternative with a busy
  buffer follows it), never a failure;
* a restart (Fig. 2-9): a NAK from a station at rest, on a line that was quiet for longer
  than any timer, is its start-up NAK. A case of ``ptpcert run`` against an IUT it restarts
  (exec:, pty:, sim:) switches the IUT on at the case's start: its first character must be
  that NAK.

Where the line never goes quiet, an STX right after a block was acknowledged begins an
exchange with both stations at rest (:meth:`LocalEvents.resync_at`). RK 512's analysis builds
on the read-ahead: it overrides ``_payload``, ``_seen`` and ``_request`` to see each block
its frame layer is handed.
"""

from __future__ import annotations

from typing import Any

from ptpcert.analysis.interface import OTHER, WAIT, Explanation, strip_section
from ptpcert.model.codes import Code
from ptpcert.model.events import SendFailed
from ptpcert.procedures.p3964.model import codec
from ptpcert.procedures.p3964.model import table as T
from ptpcert.procedures.p3964.model.codec import DLE, ETX, NAK, STX
from ptpcert.procedures.p3964.model.readings import READINGS


class LocalEvents:
    """What a 3964/3964R seat's bytes reveal, for
    :class:`~ptpcert.procedures.p3964.analysis.analyzer.P3964Analyzer` (it brings ``params``,
    ``unsendable``, :meth:`char`, :meth:`rest_gap` and :meth:`powered`)."""

    def explain(self, run, item, index: int):
        if item.kind != "byte":
            return None
        st = run.st
        b = item.value
        seat = run.judge.seat
        if b == STX and st.pending_jobs == 0 and st.state is not T.START_UP:
            payload = self._payload(run, index)
            if payload is WAIT:
                return WAIT
            aborted = run.memo.get("aborted")
            if (aborted is not None and payload in (None, aborted[0])
                    and item.start - aborted[1] < self.rest_gap()):
                return None     # the job a BREAK ended, tried again: not a new job
            if payload is None:
                payload = b"\x00"   # its block never went on the line: any data will do
            if not self._sendable(seat, payload):
                self.unsendable[(seat, index)] = payload
                return None
            return Explanation(lambda r, t, p=payload: self._request(r, t, p))
        if (b == NAK and self._quiet(run, index) and st.pending_jobs == 0 and not st.transmitting
                and st.state in (T.IDLE, T.WAIT_REPETITION)):
            return Explanation(lambda r, t: r.replace_host(self.powered(seat, t)),
                               "restarted: its start-up NAK after a quiet line (Fig. 2-9)")
        if b == DLE and st.state is T.WAIT_BUFFER:
            return Explanation(lambda r, t: r.st.set_buffer_free(t, True))
        return None

    @staticmethod
    def _request(run, t: float, payload: bytes) -> None:
        # the jobs the line revealed (the latest few: a job's block follows it at once)
        run.memo["requested"] = run.memo.get("requested", ())[-3:] + (payload,)
        run.st.request_send(t, payload)

    def before(self, item, inputs) -> bool:
        # two STXs that cross: each station decided to send before it heard the other (Fig. 2-8)
        return (item.kind == "byte" and item.value == STX
                and any(i.kind == "byte" and i.value == STX for i in inputs))

    def _quiet(self, run, index: int) -> bool:
        """Before the seat's ``index``-th item the seat was silent, and the partner sent
        nothing a station answers (NAKs only: at its own start-up), for longer than any timer:
        a NAK now is a start-up NAK."""
        j = run.judge
        item = j.obs[index]
        since = item.start - self.rest_gap()
        if index > 0 and j.obs[index - 1].t > since:
            return False
        k = run.i_in - 1
        while k >= 0 and j.inputs[k].t > since:
            q = j.inputs[k]
            if q.kind != "byte" or q.value != NAK:
                return False
            k -= 1
        return True

    def begins(self, byte: int) -> bool:
        return byte == STX

    def event(self, run, e) -> None:
        if isinstance(e, SendFailed) and e.code in (Code.LINE_BREAK, READINGS.a15_break_status_on_send, 0x1E0D):
            run.memo["aborted"] = (e.payload, e.time)

    def resync_at(self, line, k: int) -> int | None:
        """An STX right after a block was acknowledged: the end of one seat's block (DLE ETX,
        for 3964R the BCC after it; a run of DLEs before the ETX odd, so not data), the other
        seat's DLE, and nothing else before the STX."""
        first, n = line.chunk_items[k]
        seat = line.chunks[k].seat
        for j, it in enumerate(line.items[seat][first:first + n]):
            if it.kind == "byte" and it.value == STX and self._after_release(line.before(k, 8, j)):
                return j
        return None

    def _after_release(self, prev) -> bool:
        if not prev or prev[-1][1].kind != "byte" or prev[-1][1].value != DLE:
            return False
        acker = prev[-1][0]
        block = []
        for s, x in reversed(prev[:-1]):
            if s == acker:
                break
            block.insert(0, x)
        sender = "b" if acker == "a" else "a"
        tail = 1 if self.params[sender].has_bcc else 0
        data = bytes(x.value for x in block if x.kind == "byte")
        body = data[:len(data) - tail] if tail else data
        if len(body) < 2 or body[-2:] != bytes((DLE, ETX)):
            return False
        run = len(body) - 1 - len(body[:-1].rstrip(bytes((DLE,))))
        return run % 2 == 1

    def startup(self, run, item, index: int):
        if item.kind == "byte" and item.value == NAK:
            seat = run.judge.seat
            return Explanation(lambda r, t: r.replace_host(self.powered(seat, t)))
        return None

    def startup_name(self, seat: str) -> str:
        return "NAK"

    def startup_rule(self, seat: str) -> tuple[str, str, int | None]:
        row = T.TABLE[T.START_UP][T.POWER_ON]
        return strip_section(row.rule), row.ref, None

    def _sendable(self, seat: str, payload: bytes) -> bool:
        p = self.params[seat]
        return 1 <= len(payload) <= codec.MAX_BLOCK and (p.data_bits == 8 or all(x <= 0x7F for x in payload))

    @staticmethod
    def _seen(best: bytes, data: bytearray) -> bytes | None:
        """What the line showed of a block that never ended (None: nothing)."""
        out = bytes(data) if len(data) > len(best) else best
        return out or None

    def _payload(self, run, index: int) -> Any:
        """The data of the block the send job beginning with the STX ``obs[index]`` carries:
        read ahead on the line (see the module docstring). WAIT when the line has not shown it
        yet; None when the job ended without its block on the line.

        The block is read from the station's own characters: after its STX come further STXs
        (new attempts), a NAK (it gave up), or what it answers as a receiver when the partner's
        STX crossed its own, until the partner answers its latest STX with DLE; then the
        block, back to back, up to DLE ETX. A pause in the block longer than the partner waits
        (CDT) means the block was cut off and a new attempt follows."""
        j = run.judge
        a = j.analysis
        obs, inputs = j.obs, j.inputs
        seat = j.seat
        r = a.resolution
        gap_max = self.params[OTHER[seat]].cdt + 2 * self.char(seat) + r
        stx = obs[index]
        state, data, esc, best = "setup", bytearray(), False, b""
        last = last_stx = stx.t
        i = index + 1
        while True:
            if i >= len(obs):
                if not a.complete and a.known_until - last < self.rest_gap():
                    return WAIT
                return self._seen(best, data)
            it = obs[i]
            gap = it.t - last
            if state == "block" and gap > gap_max:
                if len(data) > len(best):
                    best = bytes(data)       # cut off: a new attempt follows
                state = "setup"
            if state == "setup":
                if gap > self.rest_gap():
                    return self._seen(best, data)   # the job is over without a whole block
                first = self._partner_first(inputs, last_stx, r, it.t + r, self.char(OTHER[seat]))
                v = it.value if it.kind == "byte" else None
                if first != DLE:
                    if v == STX:
                        last_stx = it.t                 # another attempt
                    elif v == NAK and first is None:
                        return self._seen(best, data)   # the station gave up
                    last, i = it.t, i + 1               # (or answered the partner's STX)
                    continue
                state, data, esc = "block", bytearray(), False
            v = it.value if it.kind != "break" else 0
            if esc:
                esc = False
                if v == DLE:
                    data.append(DLE)
                elif v == ETX:
                    return bytes(data)
                else:
                    data += bytes((DLE, v))
            elif v == DLE:
                esc = True
            else:
                data.append(v)
            if len(data) > 4 * codec.MAX_BLOCK:
                return bytes(data)
            last, i = it.t, i + 1

    @staticmethod
    def _partner_first(inputs, t0: float, r: float, t1: float, c: float) -> int | None:
        """The partner's answer to the STX the station sent at ``t0``, if it came by ``t1``:
        its first character after it, passing over an STX that crossed ours (after which a
        low-priority partner answers with DLE); failing that, within the resolution ``r``
        before ``t0``, the one closest to it. -1: a line condition; after a crossing STX, a DLE
        doubled (the first data byte of the high-priority partner's own block: the second
        right after it, ``c`` being a character time) is no answer."""
        lo, hi = 0, len(inputs)
        while lo < hi:
            mid = (lo + hi) // 2
            if inputs[mid].t <= t0:         # an STX complete at the same instant crossed it
                lo = mid + 1
            else:
                hi = mid
        crossed = lo < len(inputs) and inputs[lo].kind == "byte" and inputs[lo].value == STX
        if crossed:
            lo += 1
        if lo < len(inputs) and inputs[lo].t <= t1:
            x = inputs[lo]
            if (crossed and x.kind == "byte" and x.value == DLE and lo + 1 < len(inputs)
                    and inputs[lo + 1].kind == "byte" and inputs[lo + 1].value == DLE
                    and inputs[lo + 1].t - x.t <= c + r + 1e-4):
                return -1
        elif lo > 0 and inputs[lo - 1].t > t0 - r:
            x = inputs[lo - 1]
        else:
            return None
        return x.value if x.kind == "byte" else -1
