"""The RK 512 fuzz kit as the campaign (:mod:`ptpcert.fuzz.campaign`) gets it
(:data:`FUZZ_KIT`): the generator, the model's readings of the manual, the other readings of
its open points (:data:`ALTERNATIVE_READINGS`: our list's AMB-01..37 and N1..N7, the fields
of :class:`~ptpcert.procedures.rk512.model.readings.Rk512Readings`) under which a divergence
is explained rather than a finding, and that the examples' expectations include what the
IUT reports.
"""

from __future__ import annotations

from ptpcert.fuzz.kit import FuzzKit
from ptpcert.model.codes import Code
from ptpcert.procedures.rk512.model.readings import RK512_READINGS

from .generator import RkGenerator
from .rules import rule_of_note

#: the other reading of an open point and the change of the readings that takes it: a
#: divergence such a model shows too is not a finding
ALTERNATIVE_READINGS = [
    ("AMB-01", dict(amb01_accept_c_for_counters=True)),
    ("AMB-03", dict(amb03_accept_send_type_x=True)),
    ("AMB-10", dict(amb10_short_command_reatel=None)),
    ("AMB-10", dict(amb10_short_response_ends_request=False)),
    ("AMB-13", dict(amb13_check_byte2=True)),
    ("AMB-14", dict(amb14_address_16bit=False)),
    ("AMB-16", dict(amb16_exact_chunks=False)),
    ("AMB-17", dict(amb17_tres_start="handed_over")),
    ("AMB-18", dict(amb18_first_command_while_waiting="execute")),
    ("AMB-18", dict(amb18_passive_timeout_status=Code.PARTNER_SEQUENCE_ERROR)),
    ("AMB-20", dict(amb20_cell_fetch_limit_bytes=32)),
    ("AMB-20", dict(amb20_cell_fetch_limit_bytes=32, amb20_cell_limit_reatel=0x0C)),
    ("AMB-20", dict(amb20_serve_dx_fetch=False)),
    ("AMB-22", dict(amb22_cpu0_nibble_without_flag=0xF)),
    ("AMB-23", dict(amb23_byte9_ff_means_no_flag=False)),
    ("AMB-25", dict(amb25_extent_beyond_area="area")),
    ("AMB-31", dict(amb31_responses_first=True)),
    ("AMB-32", dict(amb32_early_response_ends_request=True)),
    ("AMB-33", dict(amb33_error_response_with_data="reatel")),
    ("N1", dict(n1_bad_id_reply_frame_id=0xFF)),
    ("N3", dict(n3_continuation_count_status=Code.SEND_LENGTH_DIFFERS)),
    ("N4", dict(n4_write_per_frame=False)),
    ("N5", dict(n5_len_over_1024_status=Code.LEN_ILLEGAL)),
    ("N6", dict(n6_db0_status=Code.INVALID_FB_PARAMETERS)),
    ("N7", dict(n7_pipelined_command_aborts=False)),
]

FUZZ_KIT = FuzzKit(RkGenerator, RK512_READINGS, tuple(ALTERNATIVE_READINGS), check_reports=True,
                   rule_of_note=rule_of_note)
