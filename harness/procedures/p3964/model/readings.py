"""Our readings of the open points of the manual (ambiguities A1..A27).

Every place where the reference model had to choose between defensible readings that
changes what the station does (on the wire, or the STATUS events it raises) is one field
here, named after its ambiguity number. :data:`READINGS` holds the best readings (the
defaults the model uses); a station can be built with other readings to check that a
conformance case grades the alternative correctly instead of failing it. Every field
changes the station's behaviour when flipped (tests/procedures/p3964/test_table.py shows how).
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Readings:
    # A1: default ADT of 3964 without BCC. Table 2-4 (550 ms) wins over the Fig. 2-10
    # legend (500 ms). No field: it is a parameter default, not a choice the station makes;
    # it lives in params.DEFAULT_ADT_MS, and a profile states the ADT it uses.

    # A2: a CDT timeout in the receiver goes through "send NAK -> wait for repetition"
    # (Fig. 2-12) rather than straight back to idle (prose). The NAK is the same; a send
    # job handed over after it waits until T_BLOCK has run out (or the repetition is in),
    # where the alternative starts it at once. The STATUS sequence differs too.
    a2_cdt_timeout_awaits_repetition: bool = True

    # A3/A5: the decision after "W+1" tests the transmission-attempt counter W, and the
    # final NAK after the last failed *transmission* attempt is sent (no field: fixed).

    # A4: every new transmission attempt starts with the setup counter X reset to 1.
    a4_reset_setup_counter_per_attempt: bool = True

    # A6: when the last transmission attempt ended through "other character during send"
    # (which already sent a NAK after the quiet wait), no second NAK is sent.
    a6_second_final_nak: bool = False

    # A7: the "quiet" CDT waits (garbage in idle, other character during send) restart on
    # every further character, so a burst of garbage yields one NAK once the line is quiet.
    a7_quiet_wait_retriggered: bool = True

    # A8: no guard times: a retry STX, a deferred STX after a conflict reception and a new
    # job after a completed one go out at once. No field: the manual sets no delay here, so
    # any delay within the partner's timers is conforming; that is a tolerance of the
    # cases' windows (like the time a station takes to answer), not a reading of a rule.

    # A9: STATUS events are raised as they happen: the specific error of every failed
    # attempt, 16#0701/16#0801 at the first repetition, 16#0709/16#070A at the final failure.
    a9_report_each_error: bool = True

    # A10: a DLE that arrives after the end sequence has started but before its last byte
    # (ETX, or the BCC for 3964R) has been sent is "DLE too early" (16#0706) and counts as
    # a failed transmission attempt; a DLE earlier in the data is "other character" (0704).
    a10_dle_in_end_sequence_too_early: bool = True

    # A11: after "DLE followed by another character" (16#0805) the receiver keeps receiving
    # and sends its NAK at the end of the block (or at the CDT timeout).
    a11_deferred_nak_after_dle_other: bool = True

    # A12: at release, T_ADT starts when the last byte of the end sequence has been sent
    # (Fig. 2-10 "send BCC -> start T_ADT"), not after DLE ETX.
    a12_release_adt_after_last_byte: bool = True

    # A13: a character with a transmission error in idle raises 16#080C at once and is then
    # treated like any other stray character: NAK once the line has been quiet for CDT.
    a13_nak_after_invalid_char_in_idle: bool = True

    # A15: the code a sender raises when BREAK aborts its job (16#080D; 16#1E0D also allowed).
    a15_break_status_on_send: int = 0x080D

    # A16: characters that arrive after STX while the receiver waits for a free buffer:
    # abandon the setup, wait for CDT of quiet, NAK (16#0802), back to idle. The alternative:
    # raise 16#0802 at once and keep waiting for a buffer (DLE if one frees in time, else
    # the NAK of T_NAKTIM, 16#080A).
    a16_garbage_during_buffer_wait_quiet_nak: bool = True

    # A17: a zero-length block (STX, DLE, DLE ETX [BCC]) is acknowledged with DLE and
    # delivered empty (the echo application ignores it). A block of more than 1024 user
    # bytes is refused with NAK at its end (16#0816).
    a17_accept_zero_length_block: bool = True

    # A18: the receiver gives up on a block after N receptions, N being its own
    # transmission-attempts parameter (Fig. 2-12 "W > 5" for N = 6; 16#0815 exists for
    # settings that differ). The alternative: always the figure's 6. On the wire it shows
    # as for A2: waiting for a repetition holds back a new send job until T_BLOCK.
    a18_receiver_uses_own_attempt_limit: bool = True

    # A19: while waiting for a repetition, a NAK from the partner (it gave up) and the
    # expiry of T_BLOCK both end the wait with 16#0815; other characters are treated as in
    # idle.
    a19_wait_repetition_code: int = 0x0815

    # A21: the collided STX of an initialization conflict counts as setup attempt 1; the
    # deferred job resumes with "2nd connection setup attempt" (Fig. 2-8), X := X + 1.
    a21_conflict_counts_collided_stx: bool = True

    # A23: a high-priority station does not restart T_ADT when the partner's STX arrives.
    a23_restart_adt_on_conflict_stx: bool = False

    # §1 item 5 / A7 / A12: every timer that waits for a character allows that character
    # one character time to arrive, because a receiver sees a character only once its stop
    # bit is in (CDT is defined between stop bit and next start bit).
    timer_grace_one_character: bool = True


READINGS = Readings()
