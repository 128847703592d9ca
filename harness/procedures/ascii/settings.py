"""The IUT settings the ASCII driver's traceability matrix is computed for
(:meth:`AsciiProcedure.rule_settings`), and the values of the catalogue's dimensions for a
profile (:func:`setting_values`; ``rules.toml`` next to this module).

Each value of each dimension occurs in at least one setting, not every combination: the
three end criteria, one and two end characters, the three send variants, the fixed-length
pause on and off, XON/XOFF and no flow control, 7 and 8 data bits, one and several buffered
frames, overwrite prevented and allowed, and a fixed length whose buffer is full by frame
count or by bytes first (with the other criteria the cases choose). RTS/CTS and the automatic use of the V.24 signals
are left out: every rule of their own needs the modem lines (untestable: no transport
carries them), and the rest is what the settings without flow control check.

The settings run the bundled reference's profile (CDT 20 ms, 9600 bit/s) with a fixed
length of 8 or 100 bytes and a wait time for XON of 2 s, so that the cases of every rule
fit their time limits.
"""

from __future__ import annotations

from typing import Any

from .model.params import BUFFER_BYTES

EC1 = {"end_criterion": "end_chars", "end_chars": [0x03]}
EC2 = {"end_criterion": "end_chars", "end_chars": [0x0D, 0x0A]}
XON = {"flow_control": "xon_xoff", "xon_wait_ms": 2000}

#: (label, profile keys) of each setting
SETTINGS: tuple[tuple[str, dict[str, Any]], ...] = (
    ("cdt 12 frames", {"end_criterion": "cdt", "buffer_frames": 12}),
    ("cdt xon_xoff 7 bits 12 frames", {"end_criterion": "cdt", "data_bits": 7, "buffer_frames": 12, **XON}),
    ("end_chars 03 up_to_end", {**EC1, "send_variant": "up_to_end"}),
    ("end_chars 0D 0A len_with_end xon_xoff", {**EC2, "send_variant": "len_with_end", **XON}),
    ("end_chars 03 len_append_end 7 bits", {**EC1, "send_variant": "len_append_end", "data_bits": 7}),
    ("fixed_length 40 no pause 7 bits", {"end_criterion": "fixed_length", "fixed_length": 40, "send_pause": False,
                                        "data_bits": 7}),
    ("fixed_length 100 xon_xoff", {"end_criterion": "fixed_length", "fixed_length": 100, **XON}),
    ("end_chars 03 one frame overwrite", {**EC1, "buffer_frames": 1, "prevent_overwrite": False}),
    ("fixed_length 100 xon_xoff 8 frames", {"end_criterion": "fixed_length", "fixed_length": 100, "buffer_frames": 8,
                                            **XON}),
)


def setting_values(params) -> dict[str, Any]:
    """The values of the catalogue's dimensions for an IUT with these parameters (see the
    header of ``rules.toml``: end_chars as a count, buffer_frames as 1 or 2..250)."""
    return {
        "end_criterion": params.end_criterion,
        "end_chars": len(params.end_chars),
        "send_variant": params.send_variant,
        "send_pause": params.send_pause,
        "flow_control": params.flow_control,
        "data_bits": params.data_bits,
        "buffer_frames": 1 if params.buffer_frames == 1 else "2..250",
        "prevent_overwrite": params.prevent_overwrite,
        "buffer_limit": buffer_limit(params),
    }


def buffer_limit(params) -> str:
    """Which limit of the receive buffer a partner reaches first (``rules.toml``, header)."""
    if params.end_criterion != "fixed_length":
        return "either"
    return "frame count" if (params.buffer_frames + 1) * params.fixed_length <= BUFFER_BYTES - 100 else "1024 bytes"


class RuleSettings:
    """The two methods of :class:`~ptpcert.procedure.Procedure` for the matrix, mixed into
    the ASCII driver's description."""

    def rule_settings(self) -> list[tuple[str, dict[str, Any], Any]]:
        """(label, dimension values, profile) for each of :data:`SETTINGS`."""
        out = []
        for label, keys in SETTINGS:
            profile = self.reference_profile(**keys)
            out.append((label, setting_values(profile.params), profile))
        return out

    def setting_values(self, params) -> dict[str, Any]:
        return setting_values(params)
