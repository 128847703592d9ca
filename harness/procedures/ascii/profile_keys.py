"""The keys of an ASCII driver profile, as the profile schema (:mod:`ptpcert.schema`) declares
them: the CDT and the character frame in ``[iut]`` (Tables 2-7, 2-8), the driver's settings in
``[ascii]`` (Tables 2-7, 2-9, 2-10). A key that the configuration does not use applies only where
``when`` says (the parameter tool greys it out, Table 2-7 footnotes 1 and 3, Table 2-9 footnotes
1, 3 and 4). What depends on another key (the CDT's minimum at a baud rate, codes with 7 data
bits, XON and XOFF different) the model's parameters check."""

from __future__ import annotations

from ptpcert.model.line import BAUD_RATES, PARITIES
from ptpcert.schema import Key

from .model.params import (END_CRITERIA, FLOW_CONTROLS, INTERFACES, MAX_BUFFER_FRAMES, MAX_CDT_MS, MAX_FRAME,
                           MIN_CDT_MS, SEND_VARIANTS, TIME_STEP_MS, V24_TIME_RANGE_MS, XON_WAIT_RANGE_MS)

_END_CHARS = {"end_criterion": ("end_chars",)}
_XON = {"flow_control": ("xon_xoff",)}

SCHEMA: tuple[Key, ...] = (
    Key("character_delay_ms", "iut", "int", "CDT: the receive criterion's pause, the watchdog and the send "
        "pause; left out: 4 ms, raised to the baud rate's minimum (reading Q3)", ref="Table 2-7",
        default=None, lo=min(MIN_CDT_MS.values()), hi=MAX_CDT_MS, unit="ms", floor=("baud_rate", MIN_CDT_MS)),
    Key("baud_rate", "iut", "choice", "the transmission rate in bit/s", ref="Table 2-8", default=9600,
        choices=BAUD_RATES),
    Key("data_bits", "iut", "choice", "data bits of the character frame", ref="Table 2-8", default=8,
        choices=(7, 8)),
    Key("parity", "iut", "choice", "parity bit of the character frame", ref="Table 2-8", default="even",
        choices=PARITIES),
    Key("stop_bits", "iut", "choice", "stop bits of the character frame", ref="Table 2-8", default=1,
        choices=(1, 2)),
    Key("end_criterion", "ascii", "choice", "how a received frame ends: a pause of CDT, end characters, or "
        "a fixed length", ref="Table 2-7", default="cdt", choices=END_CRITERIA),
    Key("end_chars", "ascii", "bytes", "the one or two end characters", ref="Table 2-7; Table A-7",
        default=[0x03], size=(1, 2), when=_END_CHARS),
    Key("fixed_length", "ascii", "int", "the frame length", ref="Table 2-7", default=240, lo=1, hi=MAX_FRAME,
        unit="bytes", when={"end_criterion": ("fixed_length",)}),
    Key("send_variant", "ascii", "choice", "what a send job puts on the line with the end-character "
        "criterion (reading Q6)", ref="§2.2.4", default="up_to_end", choices=SEND_VARIANTS, when=_END_CHARS),
    Key("send_pause", "ascii", "bool", "the CDT pause between frames sent (only the fixed-length pause can "
        "be switched off, reading Q8)", ref="§2.2.4", default=True, when={"end_criterion": ("fixed_length",)}),
    Key("flow_control", "ascii", "choice", "data flow control", ref="Table 2-9", default="none",
        choices=FLOW_CONTROLS),
    Key("xon", "ascii", "byte", "the XON code", ref="Table 2-9", default=0x11, when=_XON),
    Key("xoff", "ascii", "byte", "the XOFF code", ref="Table 2-9", default=0x13, when=_XON),
    Key("xon_wait_ms", "ascii", "int", "how long the driver waits for XON or CTS = ON (reading Q2)",
        ref="Table 2-9", default=20_000, lo=XON_WAIT_RANGE_MS[0], hi=XON_WAIT_RANGE_MS[1], step=TIME_STEP_MS,
        unit="ms", when={"flow_control": ("xon_xoff", "rts_cts")}),
    Key("rts_off_delay_ms", "ascii", "int", "the time to RTS OFF (automatic use of V.24 signals)",
        ref="Table 2-9", default=10, lo=V24_TIME_RANGE_MS[0], hi=V24_TIME_RANGE_MS[1], step=TIME_STEP_MS,
        unit="ms", when={"flow_control": ("auto_v24",)}),
    Key("data_output_wait_ms", "ascii", "int", "the data output waiting time (automatic use of V.24 "
        "signals)", ref="Table 2-9", default=10, lo=V24_TIME_RANGE_MS[0], hi=V24_TIME_RANGE_MS[1],
        step=TIME_STEP_MS, unit="ms", when={"flow_control": ("auto_v24",)}),
    Key("buffer_frames", "ascii", "int", "how many received frames the buffer holds", ref="Table 2-10",
        default=MAX_BUFFER_FRAMES, lo=1, hi=MAX_BUFFER_FRAMES),
    Key("prevent_overwrite", "ascii", "bool", "whether a full buffer refuses a new frame (false: only with "
        "one frame)", ref="Table 2-10", default=True, when={"buffer_frames": (1,)}),
    Key("interface", "ascii", "choice", "the interface variant of the module", ref="Table 1-2; Table 2-11",
        default="rs232c", choices=INTERFACES),
)
