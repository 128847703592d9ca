"""Deliberately broken variants of the reference implementation, each breaking one rule.

They prove the suite's detection power: ``ptpcert iut --mutant NAME`` runs one in real
time, ``sim:?mutant=NAME`` in virtual time; the tests run the suite against each and
check that it fails, naming the cases that caught it. A mutant is the reference station
with one action, decision or table row changed; nothing else differs. A variant overrides the
station's protected hooks (actions, decisions, ``_body``, ``_durations``, the attempt limits) or
patches rows of its table; it never touches the station's private fields.
"""

from __future__ import annotations

from .model import Params3964, Station3964
from .model import events as ev
from .model import table as T
from .model.codec import DLE, ETX, NAK, STX, bcc
from .procedure import Mutant


MUTANTS: dict[str, Mutant] = {}


def mutant(name: str, rule: str, **profile):
    def register(cls):
        cls.__name__ = "Mutant_" + name.replace("-", "_")
        MUTANTS[name] = Mutant(name, rule, cls, profile)
        return cls
    return register


def _patched(table: dict, state: str, inp: str, row: T.Row) -> dict:
    out = {s: dict(rows) for s, rows in table.items()}
    out[state][inp] = row
    return out


def _patched_states(table: dict, states, inp: str, row: T.Row) -> dict:
    for state in states:
        table = _patched(table, state, inp, row)
    return table


# ---------------------------------------------------------------- framing and BCC (send)
@mutant("bcc-without-end-sequence", "§4.1: the BCC leaves out DLE ETX")
class _(Station3964):
    def _body(self, payload):
        b = super()._body(payload)
        return b[:-1] + bytes([b[-1] ^ DLE ^ ETX]) if self.params.has_bcc else b


@mutant("bcc-includes-stx", "§4.1: the BCC includes the STX")
class _(Station3964):
    def _body(self, payload):
        b = super()._body(payload)
        return b[:-1] + bytes([b[-1] ^ STX]) if self.params.has_bcc else b


@mutant("bcc-dle-counted-once", "§4.1 Note: the BCC counts a doubled DLE once")
class _(Station3964):
    def _body(self, payload):
        b = super()._body(payload)
        return b[:-1] + bytes([bcc(payload)]) if self.params.has_bcc else b


@mutant("no-dle-doubling", "§3 item 1: data DLEs are not doubled")
class _(Station3964):
    def _body(self, payload):
        b = payload + bytes([DLE, ETX])
        return b + bytes([bcc(payload)]) if self.params.has_bcc else b


@mutant("bcc-doubled-when-dle", "§3 item 5: a BCC equal to DLE is doubled")
class _(Station3964):
    def _body(self, payload):
        b = super()._body(payload)
        return b + bytes([DLE]) if self.params.has_bcc and b[-1] == DLE else b


# ---------------------------------------------------------------- receiving
@mutant("no-dle-undoubling", "§3 item 2: DLE DLE in the data is stored as two bytes")
class _(Station3964):
    def _a_store_doubled_dle(self, v):
        self._store(DLE, in_bcc=False)  # the first DLE is kept as data; the BCC is unchanged
        super()._a_store_doubled_dle(v)


@mutant("bcc-not-checked", "§8.4 item 2: the received BCC is not compared")
class _(Station3964):
    def _d_bcc_check(self):
        return T.EVALUATE


@mutant("ack-at-etx-in-3964r", "Table 2-3: a 3964R receiver answers at DLE ETX, before the BCC")
class _(Station3964):
    def _d_after_etx(self):
        return T.EVALUATE


@mutant("dle-other-accepted", "§8.3 item 3: DLE followed by another character is taken as data (no 16#0805)")
class _(Station3964):
    TABLE = _patched(T.TABLE, T.WAIT_ETX, T.OTHER, T.Row("store", T.RECEIVE))


@mutant("no-length-limit", "§8.3 item 6: blocks longer than 1024 bytes are accepted")
class _(Station3964):
    def _note(self, code):
        if code != ev.FRAME_TOO_LONG:
            super()._note(code)


@mutant("parity-error-ignored", "§8.3 item 4: a character with a parity error is taken as valid")
class _(Station3964):
    def receive_invalid(self, now, value=0):
        self.receive(now, value)


@mutant("parity-error-nak-at-once", "§8.3 item 4: a parity error inside a block is answered by NAK at once")
class _(Station3964):
    TABLE = _patched(T.TABLE, T.RECEIVE, T.INVALID, T.Row("note_invalid_character", T.NAK_CHECK))


@mutant("no-cdt-after-dle", "§8.2 item 3: no timeout for the first character after the receiver's DLE")
class _(Station3964):
    def _d_receive_entry(self):
        out = super()._d_receive_entry()
        if out == T.RECEIVE:
            self._stop_timer()
        return out


@mutant("repetition-refused", "§8.5 item 2: a repetition after NAK is not answered")
class _(Station3964):
    TABLE = _patched(T.TABLE, T.WAIT_REPETITION, T.STX, T.Row("ignore", T.SAME))


# ---------------------------------------------------------------- idle and start-up
@mutant("no-startup-nak", "§6: no NAK at start-up")
class _(Station3964):
    def _a_send_startup_nak(self, v):
        pass


@mutant("idle-nak-without-quiet-wait", "§8.1 item 3: a stray character is NAKed at once, not after CDT")
class _(Station3964):
    def _a_start_quiet_wait(self, v):
        self._start_timer(T.T_CDT, 0.0)


@mutant("idle-stray-ignored", "§8.1 item 3: stray characters in idle are never answered with NAK")
class _(Station3964):
    def _a_quiet_nak(self, v):
        self._emit(ev.Status(self.now, ev.RX_SETUP_ERROR, "receive"))


@mutant("nak-in-idle-answered", "§8.1 item 2: a NAK in idle is treated as a stray character")
class _(Station3964):
    TABLE = _patched(T.TABLE, T.IDLE, T.NAK, T.Row("start_quiet_wait", T.IDLE_JUNK))


# ---------------------------------------------------------------- attempts and acknowledgements (send)
@mutant("setup-attempts-plus-one", "§7.1 item 5: one STX more than the setup attempts")
class _(Station3964):
    def _setup_limit(self):
        return self.params.setup_attempts + 1


@mutant("setup-attempts-minus-one", "§7.1 item 5: one STX fewer than the setup attempts")
class _(Station3964):
    def _setup_limit(self):
        return self.params.setup_attempts - 1


@mutant("tx-attempts-without-first", "Table 2-4: the first attempt is not counted (one block too many)")
class _(Station3964):
    def _tx_limit(self):
        return self.params.transmission_attempts + 1


@mutant("no-final-setup-nak", "§7.1 item 6: no NAK after the last failed setup attempt")
class _(Station3964):
    def _d_setup_check(self):
        if self.job.x <= self._setup_limit():
            return super()._d_setup_check()
        self._fail_job(ev.SETUP_ATTEMPTS_EXCEEDED)
        return T.IDLE


@mutant("no-final-tx-nak", "§7.5 item 1: no NAK after the last failed transmission attempt")
class _(Station3964):
    def _d_tx_check(self):
        if self.job.w <= self._tx_limit():
            return super()._d_tx_check()
        self._fail_job(ev.TX_ATTEMPTS_EXCEEDED)
        return T.IDLE


@mutant("nak-after-data-nak", "§7.2 item 3: a NAK during the data is answered with a NAK of its own")
class _(Station3964):
    def _a_send_refused(self, v):
        super()._a_send_refused(v)
        self._send(bytes([NAK]))


@mutant("no-quiet-before-nak", "§7.2 item 4: after another character during the data, NAK at once (no CDT wait)")
class _(Station3964):
    def _a_send_interrupted(self, v):
        super()._a_send_interrupted(v)
        self._start_timer(T.T_CDT, 0.0)


@mutant("adt-half", "Table 2-4: the sender waits only half the ADT for DLE")
class _(Station3964):
    def _durations(self):
        cdt, adt = super()._durations()
        return cdt, adt / 2


@mutant("cdt-half", "Table 2-4: the receiver times out after half the CDT")
class _(Station3964):
    def _durations(self):
        cdt, adt = super()._durations()
        return cdt / 2, adt


# ---------------------------------------------------------------- priority
@mutant("high-priority-yields", "§9 item 4: a high-priority station answers the partner's STX with DLE",
        priority="high")
class _(Station3964):
    def _d_priority(self):
        self._stop_timer()
        self.deferred, self.job = self.job, None
        self._a_begin_reception(0)
        return T.RECEIVE_ENTRY


@mutant("low-priority-insists", "§9 item 3: a low-priority station ignores the partner's STX", priority="low")
class _(Station3964):
    TABLE = _patched(T.TABLE, T.WAIT_SETUP_ACK, T.STX, T.Row("ignore", T.SAME))  # T_ADT keeps running


# ---------------------------------------------------------------- BREAK
@mutant("break-as-data", "§10 item 5: a BREAK is read as a 00 character")
class _(Station3964):
    def line_break(self, now):
        self.receive(now, 0x00)


@mutant("nak-after-break", "§10 item 5: a NAK is sent after a BREAK")
class _(Station3964):
    def _a_abandon_reception(self, v):
        super()._a_abandon_reception(v)
        self._send(bytes([NAK]))

    def _a_report_break(self, v):
        super()._a_report_break(v)
        self._send(bytes([NAK]))


@mutant("retry-after-break", "§7.6: a BREAK during sending is followed by a new attempt")
class _(Station3964):
    TABLE = _patched_states(T.TABLE, T.SENDER_STATES, T.BREAK, T.Row("abort_job", T.TX_CHECK))

    def _a_abort_job(self, v):
        self._cancel_tx()
        self._emit(ev.Status(self.now, ev.LINE_BREAK, "send"))
        self.job.w += 1
