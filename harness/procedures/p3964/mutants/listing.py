"""The 3964(R) broken variants in the order they are listed: :data:`MUTANTS`.

Part of :mod:`ptpcert.procedures.p3964.mutants`. The topic modules are grouped by the part
of the procedure their variants break; ``ptpcert iut --list-mutants`` and the kill matrix
(``benchmarks/kill_matrix.py``) list them in the order they were written instead: first the
variants of the procedure's main rules, from the frame to BREAK, then those made for
single cases of the rules catalogue, in the order of those cases. :data:`ORDER` keeps that
order; importing this module fails if a variant is missing from it or named twice.
"""

from __future__ import annotations

from ptpcert.procedure import Mutant

from . import attempts, line, receiving, sending, timers  # noqa: F401  (they enter their variants)
from .registry import REGISTERED

__all__ = ["MUTANTS", "ORDER"]

#: the names of the variants, in the order they are listed
ORDER: tuple[str, ...] = (
    # the procedure's main rules: frame and BCC, receiving, idle and start-up, attempts and
    # acknowledgements, timers, priority, BREAK
    "bcc-without-end-sequence", "bcc-includes-stx", "bcc-dle-counted-once", "no-dle-doubling",
    "bcc-doubled-when-dle", "no-dle-undoubling", "bcc-not-checked", "ack-at-etx-in-3964r",
    "dle-other-accepted", "parity-error-ignored", "parity-error-nak-at-once", "no-cdt-after-dle",
    "repetition-refused", "no-startup-nak", "idle-nak-without-quiet-wait", "idle-stray-ignored",
    "nak-in-idle-answered", "setup-attempts-plus-one", "setup-attempts-minus-one",
    "tx-attempts-without-first", "no-final-setup-nak", "no-final-tx-nak", "nak-after-data-nak",
    "no-quiet-before-nak", "adt-half", "cdt-half", "high-priority-yields", "low-priority-insists",
    "break-as-data", "nak-after-break", "retry-after-break",
    # made for single cases of the rules catalogue, in the order of those cases
    "dle-pair-rescanned", "bcc-character-error-ignored", "character-error-after-dle-nak-at-once",
    "corrupted-etx-ends-block", "corrupted-stx-accepted", "dle-during-data-is-acknowledgement",
    "stx-during-data-is-conflict", "character-error-during-data-ignored",
    "sender-nak-per-character", "stray-nak-per-character", "setup-counter-per-cause",
    "transmission-counter-per-cause", "setup-exhaustion-retries-block",
    "setup-counter-never-reset", "transmission-counter-never-reset",
    "setup-counter-spent-per-attempt", "receive-counter-never-reset",
    "receiver-locked-after-limit", "receiver-locked-after-t-block",
    "receiver-locked-after-partner-nak", "buffer-wait-too-short", "buffer-wait-garbage-accepted",
    "cdt-half-after-data-dle", "3964-waits-for-bcc", "partner-stx-refuses-setup",
    "break-ignored-waiting-for-etx", "break-ignored-waiting-for-bcc",
    "break-ignored-in-idle-quiet-wait", "break-ignored-in-sender-quiet-wait",
    "break-ignored-waiting-for-buffer", "zero-length-unanswered", "overlong-block-unanswered",
    "line-length-overflow-unanswered", "bcc-eighth-bit-set",
)

_twice = sorted({name for name in ORDER if ORDER.count(name) > 1})
if _twice or set(ORDER) != set(REGISTERED):
    raise ImportError(f"ORDER must name every 3964 variant once: not listed {sorted(set(REGISTERED) - set(ORDER))}, "
                      f"not a variant {sorted(set(ORDER) - set(REGISTERED))}, listed twice {_twice}")

#: every 3964(R) broken variant by name, in :data:`ORDER`
MUTANTS: dict[str, Mutant] = {name: REGISTERED[name] for name in ORDER}
