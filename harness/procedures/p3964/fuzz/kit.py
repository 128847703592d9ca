"""The 3964(R) fuzz kit as the campaign (:mod:`ptpcert.fuzz.campaign`) gets it
(:data:`FUZZ_KIT`): the generator, the model's readings of the manual, and the other
readings of its open points (:data:`ALTERNATIVE_READINGS`, docs/readings.md) under which a
divergence is explained rather than a finding.
"""

from __future__ import annotations

from ptpcert.fuzz.kit import FuzzKit

from ..model.readings import READINGS
from .generator import Generator
from .rules import rule_of_note

#: the other reading of an open point (docs/readings.md) and the change of the readings that
#: takes it: a divergence such a model shows too is not a finding
ALTERNATIVE_READINGS = [
    ("A6", dict(a6_second_final_nak=True)),
    ("A7", dict(a7_quiet_wait_retriggered=False)),
    ("A11", dict(a11_deferred_nak_after_dle_other=False)),
    ("A12", dict(a12_release_adt_after_last_byte=False)),
    ("A13", dict(a13_nak_after_invalid_char_in_idle=False)),
    ("A17", dict(a17_accept_zero_length_block=False)),
    ("A19", dict(a19_wait_repetition_code=0x0808)),
    ("A21", dict(a21_conflict_counts_collided_stx=False)),
    ("A23", dict(a23_restart_adt_on_conflict_stx=True)),
    ("A4", dict(a4_reset_setup_counter_per_attempt=False)),
    ("A10", dict(a10_dle_in_end_sequence_too_early=False)),
]

FUZZ_KIT = FuzzKit(Generator, READINGS, tuple(ALTERNATIVE_READINGS), rule_of_note=rule_of_note)
