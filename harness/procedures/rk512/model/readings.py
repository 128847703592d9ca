"""Our readings of the open points of the manual's RK 512 description.

Every place where the RK 512 model had to choose between defensible readings, and the
choice changes what is on the wire (or which STATUS event is reported), is one field of
:class:`Rk512Readings`, named after the open point: ``ambNN_`` for the points of our list
of the manual's ambiguities, ``nN_`` for points found while building the model that the
list does not name. :data:`RK512_READINGS` holds the readings the model uses by default; a
station built with other readings lets cases and the fuzzer accept every defensible one.

The open points that change nothing on the wire have no field (a comment says why).
"""

from __future__ import annotations

from dataclasses import dataclass, field

from ptpcert.model.codes import Code


@dataclass(frozen=True)
class Rk512Readings:
    # AMB-01: the counter data type. Table 2-1 prints "'C' (5AH)"; 5Ah is 'Z' (German
    # Zaehler), as every other letter of the table is German (E inputs, A outputs, M flags)
    # and Table 6-7 lists R_TYP C with "(Z)". A requester sends 5Ah; a responder refuses
    # 43h ('C') as an invalid type (16#0604, REATEL 10h) unless told to accept it.
    amb01_counter_letter: int = 0x5A
    amb01_accept_c_for_counters: bool = False

    # AMB-02: T_RES. Figs. 2-18/2-19 say "5 s (7 s, 10 s) depending on the transmission
    # rate", the CP 341's prose 10 s for every rate. Reading: 10 s is the default when a
    # profile gives no response_time_ms (params.default_response_time_ms); the figures'
    # values (5 s at >= 1200 bit/s, 7 s at 600, 10 s at 300 bit/s) are the shortest a
    # partner may use, so a case whose outcome hinges on T_RES in between accepts both
    # (the TRES_MIN of the cases). No field: the value is a parameter.

    # AMB-03: SEND to a DX. Table 2-1: byte 3 'O' (4Fh), byte 4 only 'D' when sending;
    # Table 6-5 prints "AD" for DX too (a copy error). A requester sends 'O' 'D'; a
    # responder refuses byte 4 'X' in a SEND (16#0604, REATEL 10h).
    amb03_send_dx_letter: int = 0x4F
    amb03_accept_send_type_x: bool = False

    # AMB-04/AMB-06/AMB-12/AMB-24/AMB-30: misprints (the command letters are A, O, E; a
    # FETCH command has no data; swapped column titles; inputs printed as outputs; a figure
    # label): no choice left, no field.

    # AMB-07: coordination-flag polarity. Data are transferred while the flag is 0; a flag
    # of 1 locks the area (16#060F, REATEL 32h).
    amb07_locked_value: int = 1

    # AMB-08: the responder sets the flag to 1 when the whole transfer is complete (the
    # user program resets it to 0 to allow the next one).
    amb08_set_flag_after_transfer: bool = True

    # AMB-09: a CP 341 serves a FETCH only with P_RCV_RK called; the model always serves
    # (the reference IUT is passive always). No field.

    # AMB-10: a frame too short for its kind (16#0610) has no REATEL in Table 8-3. Reading:
    # the responder answers a too-short command (fewer than 10 bytes for a first command,
    # fewer than 4 for a continuation; frames of 1..2 bytes when it awaits no response)
    # with the length-error number 34h, as it answers every accepted command (§2.2.3
    # "Response message frame"); None: no answer at all.
    amb10_short_command_reatel: int | None = 0x34
    # ... and a requester that receives a response of fewer than 4 bytes reports 16#0610
    # (AMB-19: the event covers responses too) and ends the request with it; False: it
    # reports 16#0610 and otherwise ignores the frame, waiting on (T_RES decides).
    amb10_short_response_ends_request: bool = True

    # AMB-11: 16#0301 under two REATELs: the model never raises 0301 on the passive side
    # (it reports the class-06 event of the byte in error). No field.

    # AMB-13: bytes 2 (and response byte 3) are not checked: no event exists for them. A
    # response with byte 3 not 00h is a command by the classification of §2.2.3. True: a
    # command byte 2 other than 00h is refused like a bad byte 1 (16#0601, REATEL 10h).
    amb13_check_byte2: bool = False

    # AMB-14: the address of the byte and cell areas (M, E, A, T, Z) is a 16-bit value in
    # bytes 5/6 (byte 5 = 00h for 0..255). False: byte 5 is ignored, byte 6 alone is the
    # address.
    amb14_address_16bit: bool = True

    # AMB-15: timers and counters count one word per cell: consistent, no field.

    # AMB-16: every frame but the last carries exactly 128 data bytes; a responder refuses
    # any other split (SEND frame length wrong: 16#060B / continuation 16#0611, REATEL 34h).
    # False: a SEND may be split into frames of 1..128 bytes in any way, as long as the
    # total is right and no frame overshoots it.
    amb16_exact_chunks: bool = True

    # AMB-17: where T_RES runs. "acknowledged": from the partner's DLE that accepts the
    # command block (3964(R) repetitions of the command do not count) to the complete
    # reception of the response block (its repetitions do count). "handed_over": from the
    # moment the command is handed to the link.
    amb17_tres_start: str = "acknowledged"

    # AMB-18: the responder's T_RES (waiting for a continuation command) expires: the
    # request is aborted without a frame; the STATUS number is not given. Reading: the
    # event of a monitoring time that expired without the partner's frame, 16#0A05.
    amb18_passive_timeout_status: int = Code.RESPONSE_TIMEOUT
    # ... and a first command that arrives while a continuation is expected aborts the open
    # request (Fig. 2-19) and is answered with REATEL 36h (16#060E), not executed
    # ("refuse"); "execute": it is served as a new request.
    amb18_first_command_while_waiting: str = "refuse"

    # AMB-19: class-06 events are reported by the receive FB (side "receive"), except
    # 16#0610 for a short response, which the requester reports (side "send"). No field.

    # AMB-20: a CP 341 limits a partner's FETCH of timers or counters to 32 bytes (§6.3.2
    # "Providing data") and does not list DX as a source. The model is a partner with the
    # memory of its parameters: no limit (None) and DX served. With a limit, a longer
    # FETCH is refused with 16#0608 and the given REATEL (34h or 0Ch: not specified).
    amb20_cell_fetch_limit_bytes: int | None = None
    amb20_cell_limit_reatel: int = 0x34
    amb20_serve_dx_fetch: bool = True

    # AMB-21: a SEND to a DX ('O') is stored in the DX named by bytes 5/6 (the model has DX
    # areas); on a CP 341 it goes to P_RCV_RK's DB_NO/DBB_NO. Visible only through a later
    # FETCH of the DX. No field.

    # AMB-22: CPU numbers. A requester sends nibble 0h for CPU 0 without a flag (byte 10
    # 0Fh; alternative Fh, "not given": FFh); a responder accepts the high nibbles 0..4 and
    # Fh (16#060A, REATEL 0Ch for 5h..Eh).
    amb22_cpu0_nibble_without_flag: int = 0x0
    amb22_accepted_cpu_nibbles: frozenset[int] = field(default=frozenset((0, 1, 2, 3, 4, 0xF)))

    # AMB-23: which data types may carry a coordination flag: all of them. Byte 9 = FFh
    # means "no flag" whatever the low nibble of byte 10 (False: the nibble must then be
    # Fh, else 16#0609). A flag byte outside the flag area or a bit number above 7 is
    # 16#0609, REATEL 0Ch.
    amb23_byte9_ff_means_no_flag: bool = True

    # AMB-25: a request that starts inside its area but extends beyond its end.
    # "length": the length is not allowed (16#0608, REATEL 34h, the Table 8-3 mapping of
    # the event for bytes 7/8); "area": the area is too short (DB/DX: 16#0606, REATEL 14h;
    # the other areas: 16#0607, REATEL 0Ch, as the class-09 texts describe them).
    amb25_extent_beyond_area: str = "length"

    # AMB-26: 16#060E / 16#0A01 are raised at any request size (the manual's remark that
    # they cannot occur below 128 bytes is not a rule). No field.

    # AMB-27/28/29: the link below (3964 allowed, its ADT default, NAK = 15h) belongs to the
    # link's parameters and readings. No field.

    # AMB-31: quasi-full-duplex ordering. A station hands its frames to the link one at a
    # time, in the order they became ready (a command of its own may go before a response
    # it owes, Fig. 2-17). True: a response that is ready goes before a command of its own.
    amb31_responses_first: bool = False

    # AMB-32: "response frame received before continuation frame sent" (16#0A01) is an
    # extra response that arrives while the requester's (continuation) command has not been
    # acknowledged yet. It is reported (not final) and the request goes on: its command is
    # with the link already and goes out, and its own answer is awaited. Ending the request
    # instead (True) leaves that command on the line unanswered-for, and the next request's
    # command would follow it before its answer (depth 1, §2.2.3 "Quasi-full-duplex").
    amb32_early_response_ends_request: bool = False

    # AMB-33: an error response (REATEL not 00h) that carries data. "length": it is a
    # response of the wrong length (SEND: 16#0A04, FETCH: 16#0A03); "reatel": the REATEL is
    # reported (class 09) and the data ignored.
    amb33_error_response_with_data: str = "length"

    # AMB-34: odd FETCH lengths are padded (one more byte asked for) only for word areas;
    # the byte areas M, E, A carry LEN bytes. True: byte areas are padded to even too.
    amb34_pad_byte_areas: bool = False

    # AMB-35/36/37: CPU-side delays, Hamming distances, a missing appendix: no field.

    # n1: the reply to a command whose byte 1 is neither 00h nor FFh (16#0601, REATEL 10h)
    # goes out as a first response (byte 1 = 00h): there is no frame id to mirror.
    n1_bad_id_reply_frame_id: int = 0x00

    # n2: the order in which a responder checks a first command; with several errors in one
    # frame the first one found decides the REATEL. Byte 1 is judged before all of them (it
    # decides whether the frame is a first command at all), and a frame of fewer than 4
    # bytes is too short before anything else. Then the CP-level checks of the frame (bytes
    # 2, 3, 4, the 10-byte minimum) and the CPU-level ones (CPU state, block, address,
    # length, flag, CPU number, data count, flag lock).
    n2_check_order: tuple[str, ...] = (
        "byte2", "byte3", "byte4", "short", "cpu_stop", "block", "address",
        "length", "flag", "cpu", "data", "lock",
    )

    # n3: a SEND continuation frame with the wrong number of data bytes: the frame length
    # differs from what the header announced (16#0611); the first frame's wrong count is
    # 16#060B ("SEND frame longer or shorter than expected"). Both send REATEL 34h.
    n3_continuation_count_status: int = Code.FRAME_LENGTH_DIFFERS

    # n4: SEND data are written to the CPU frame by frame, each before its response (§2.2.3:
    # the response follows the transfer into the CPU); a request aborted halfway leaves the
    # frames already answered in memory. False: written only when the last frame arrived.
    n4_write_per_frame: bool = True

    # n5: a request over 1024 bytes is refused locally with 16#0517 ("transmission length
    # > 1 KB"); LEN 0 with 16#1E41 (LEN outside 1..1024).
    n5_len_over_1024_status: int = Code.LENGTH_INVALID_FOR_CP

    # n6: a DB/DX number 0 in a request is refused locally with 16#0514 ("DB/DX number too
    # low"); 16#0301 (invalid FB parameters, "e.g. DB 0") is the alternative.
    n6_db0_status: int = Code.ADDRESS_OUT_OF_RANGE

    # n7: a command (first or continuation) that arrives before the responder has sent the
    # response it owes (16#060E, REATEL 36h) also aborts the open request: after its
    # response the responder waits for no continuation. False: the open request goes on.
    n7_pipelined_command_aborts: bool = True


RK512_READINGS = Rk512Readings()

#: The checks a responder can make on a first command, for n2_check_order.
CHECKS = frozenset(RK512_READINGS.n2_check_order)
