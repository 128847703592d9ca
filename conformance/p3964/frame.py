"""The character frame (§2.1 Asynchronous transmission; Table 2-5): the IUT uses the baud
rate, data bits, parity and stop bits of its profile."""

from ._build import case, receive_block

#: the frame's parity bit of a character, under each parity; a byte whose parity bit is 0
#: (space) puts a 0 where a receiver with no parity expects its stop bit, and breaks the
#: parity of a receiver with the other parity
_PARITY_BIT = {
    "even": lambda ones: ones % 2,        # even parity: the bit makes the number of ones even
    "odd": lambda ones: 1 - ones % 2,
}


def frame_payload(p) -> bytes:
    """Characters that an IUT with another frame than ``p``'s cannot receive intact: for even
    or odd parity, bytes whose parity bit is 0 (a receiver without parity takes it for a
    missing stop bit, one with the other parity for a parity error); without parity, bytes of
    both kinds (a receiver that expects a parity bit of either sense finds one wrong). Sent back
    to back, so a receiver that expects 2 stop bits finds the next start bit in the second."""
    top = 0x80 if p.data_bits == 7 else 0x100
    candidates = [b for b in range(0x30, top) if b not in (0x10,)]
    ones = {b: bin(b).count("1") for b in candidates}
    if p.parity in _PARITY_BIT:
        bit = _PARITY_BIT[p.parity]
        chosen = [b for b in candidates if bit(ones[b]) == 0][:8]
    else:
        even = [b for b in candidates if ones[b] % 2 == 0][:4]
        odd = [b for b in candidates if ones[b] % 2 == 1][:4]
        chosen = [x for pair in zip(even, odd) for x in pair]
    return bytes(chosen)


def cases(p):
    payload = frame_payload(p)
    return [
        case(p, "FRAME.PROFILE-FRAME", "The IUT receives characters whose frame only its profile's settings read intact",
             "§2.1 Asynchronous transmission; Table 2-5",
             f"A station receives with the character frame it is assigned ({p.baud_rate} bit/s, {p.data_bits} data bits, "
             f"parity {p.parity}, {p.stop_bits} stop bit{'s' if p.stop_bits != 1 else ''} in this profile): a block whose characters a "
             "receiver with another parity or number of stop bits takes for errors is accepted.",
             "character-frame", "receiver", receive_block(payload, p),
             delivered=[payload], echo_after=[payload], provenance="[S]", rules=["3964.FRAME.SETTINGS"],
             extra={"check_line_settings": True},
             notes="On a real serial port the tester sends with the profile's frame, so an IUT set to another frame "
                   "sees parity or framing errors and refuses the block. Where the transport can read the IUT's "
                   "own line settings (a pseudo-terminal's termios), they are compared with the profile too "
                   "(extra.check_line_settings)."),
    ] + ([
        case(p, "FRAME.SEVEN-BIT", "With 7 data bits the IUT receives and sends the values up to 7F, BCC included",
             "Table 2-5 (data bits 7, 8); Table A-5",
             "With 7 data bits a character carries 00..7F: a block of the highest values, whose BCC is a 7-bit value too, is received and sent back unchanged.",
             "character-frame", "receiver", receive_block(b"\x7f\x7e\x7d\x40\x3f", p),
             delivered=[b"\x7f\x7e\x7d\x40\x3f"], echo_after=[b"\x7f\x7e\x7d\x40\x3f"], provenance="[S][I]",
             rules=["3964.FRAME.SEVEN-BIT"]),
    ] if p.data_bits == 7 else [])
