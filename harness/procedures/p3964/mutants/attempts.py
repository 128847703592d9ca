"""3964(R) variants that break a send job's setup and transmission attempts (Fig. 2-10, Table 2-4).

Part of :mod:`ptpcert.procedures.p3964.mutants`. A send job counts its setup attempts (X)
and its transmission attempts (W); these variants allow one too many or one too few, leave
out the NAK after the last one, start a new block when the setup attempts are used up,
keep a counter per kind of failure, or carry a counter over from the last job or block. A ``# SUITE...`` comment above a variant names the case of the
rules catalogue it was made for.
"""

from __future__ import annotations

from ptpcert.model.codes import Code
from ptpcert.procedures.p3964.model import table as T
from ptpcert.procedures.p3964.model.station import Station3964

from .registry import mutant


# ---------------------------------------------------------------- the limits
@mutant("setup-attempts-plus-one", "Fig. 2-10 'X <= 6 / X > 6'; Table 2-4: one STX more than the setup attempts")
class _(Station3964):
    def _setup_limit(self):
        return self.params.setup_attempts + 1


@mutant("setup-attempts-minus-one", "Fig. 2-10 'X <= 6 / X > 6'; Table 2-4: one STX fewer than the setup attempts")
class _(Station3964):
    def _setup_limit(self):
        return self.params.setup_attempts - 1


@mutant("tx-attempts-without-first", "Table 2-4: the first attempt is not counted (one block too many)")
class _(Station3964):
    def _tx_limit(self):
        return self.params.transmission_attempts + 1


@mutant("no-final-setup-nak", "§2.2.2 Send/setup; Fig. 2-10 'send NAK': no NAK after the last failed setup attempt")
class _(Station3964):
    def _d_setup_check(self):
        if self.job.x <= self._setup_limit():
            return super()._d_setup_check()
        self._fail_job(Code.SETUP_ATTEMPTS_EXCEEDED)
        return T.IDLE


@mutant("no-final-tx-nak", "Fig. 2-10 'send NAK': no NAK after the last failed transmission attempt")
class _(Station3964):
    def _d_tx_check(self):
        if self.job.w <= self._tx_limit():
            return super()._d_tx_check()
        self._fail_job(Code.TX_ATTEMPTS_EXCEEDED)
        return T.IDLE


# SUITE.SEND.SETUP-EXHAUSTED-ENDS-JOB
@mutant("setup-exhaustion-retries-block",
        "Fig. 2-10 'X > 6', 'send NAK': used-up setup attempts start a new transmission attempt instead of ending the job")
class _(Station3964):
    def _d_setup_check(self):
        job = self.job
        if job.x > self._setup_limit() and job.w < self._tx_limit():
            job.w += 1
            job.x = 1
            self._send_stx()
            return T.WAIT_SETUP_ACK
        return super()._d_setup_check()


# ---------------------------------------------------------------- the counters
# SUITE.SEND.SETUP-ATTEMPTS-MIXED
class _PerCause(Station3964):
    """A job's attempt counter (``counter``: the job's ``x`` or ``w``) kept per kind of failure."""
    counter = "x"

    def _a_start_job(self, v):
        super()._a_start_job(v)
        self.causes = {}

    def count_cause(self, cause):
        self.causes[cause] = self.causes.get(cause, 0) + 1
        setattr(self.job, self.counter, 1 + max(self.causes.values()))


@mutant("setup-counter-per-cause", "Fig. 2-10 'X+1': each kind of failed setup (NAK, timeout, character error) has a counter of its own")
class _(_PerCause):
    counter = "x"

    def _a_setup_refused(self, v):
        super()._a_setup_refused(v)
        self.count_cause("refused")

    def _a_setup_invalid_character(self, v):
        super()._a_setup_invalid_character(v)
        self.count_cause("invalid")

    def _a_setup_timeout(self, v):
        super()._a_setup_timeout(v)
        self.count_cause("timeout")


# SUITE.RELEASE.ATTEMPTS-MIXED
@mutant("transmission-counter-per-cause",
        "Table 2-4 transmission attempts; Fig. 2-10 'W+1': each kind of failed attempt has a counter of its own")
class _(_PerCause):
    counter = "w"

    def _a_send_refused(self, v):
        super()._a_send_refused(v)
        self.count_cause("data NAK")

    def _a_release_refused(self, v):
        super()._a_release_refused(v)
        self.count_cause("refused")

    def _a_release_invalid_character(self, v):
        super()._a_release_invalid_character(v)
        self.count_cause("invalid")

    def _a_release_timeout(self, v):
        super()._a_release_timeout(v)
        self.count_cause("timeout")

    def _a_abort_nak(self, v):
        super()._a_abort_nak(v)
        self.count_cause("other")


class _CarriedOver(Station3964):
    """A job's attempt counter (``counter``: the job's ``x`` or ``w``) that a new job takes
    over from the last one acknowledged instead of starting at 1."""
    counter = "x"

    def _a_start_job(self, v):
        carried = self.deferred is None and getattr(self, "last_" + self.counter, None)
        super()._a_start_job(v)
        if carried:
            setattr(self.job, self.counter, carried)

    def _a_release_acknowledged(self, v):
        setattr(self, "last_" + self.counter, getattr(self.job, self.counter))
        super()._a_release_acknowledged(v)


# SUITE.COUNTERS.SETUP-PER-JOB
@mutant("setup-counter-never-reset", "Fig. 2-10 'send request', 'X := 1': a new job goes on with the setup counter of the last one")
class _(_CarriedOver):
    counter = "x"


# SUITE.COUNTERS.TRANSMISSION-PER-JOB
@mutant("transmission-counter-never-reset",
        "Fig. 2-10 'send request', 'W := 1': a new job goes on with the transmission counter of the last one")
class _(_CarriedOver):
    counter = "w"


# SUITE.COUNTERS.SETUP-PER-ATTEMPT
@mutant("setup-counter-spent-per-attempt",
        "Fig. 2-10 'X := 1': a repeated block gets a single setup attempt (the counter is set to its limit)")
class _(Station3964):
    def _d_tx_check(self):
        out = super()._d_tx_check()
        if out is T.WAIT_SETUP_ACK:
            self.job.x = self._setup_limit()
        return out
