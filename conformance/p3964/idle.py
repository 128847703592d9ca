"""Idle (Fig. 2-11; 3964r.md §8.1)."""

from ._build import NAK, case, expect, nak_after_cdt, receive_block, send, send_error, silence


def cases(p):
    out = [
        case(p, "IDLE.NAK-IGNORED", "A NAK received in idle is ignored",
             "§2.2.2 Receive/setup; 3964r.md §8.1 item 2",
             "A station in idle gives no answer and raises no error for a NAK.",
             "idle", "idle", [send(NAK, note="NAK"), silence("2*CDT + ADT", note="no answer")],
             provenance="[S]"),
    ]
    for value, name in ((0x41, "CHARACTER"), (0x10, "DLE"), (0x03, "ETX"), (0x00, "NUL")):
        out.append(case(
            p, f"IDLE.STRAY-{name}", f"A stray {name} ({value:02X}) in idle gets a NAK after CDT of quiet",
            "§2.2.2 Receive/setup; Fig. 2-11; Table 8-1 16#0802; 3964r.md §8.1 item 3",
            "Any character other than STX or NAK received in idle is answered with NAK once the character delay time has expired (16#0802), not before.",
            "idle", "idle", [send(bytes([value]), note="a stray character"), nak_after_cdt()],
            iut=(["16#0802"], ()), provenance="[S]"))
    out += [
        case(p, "IDLE.STRAY-THEN-BLOCK", "After answering a stray character the IUT receives the next block",
             "§2.2.2 Receive/setup; 3964r.md §8.1 item 3",
             "The NAK for stray characters returns the procedure to idle, where STX starts a reception.",
             "idle", "receiver",
             [send("41"), nak_after_cdt()] + receive_block(b"\x51", p),
             iut=(["16#0802"], ()), delivered=[b"\x51"], echo_after=[b"\x51"], provenance="[S][I]"),
        case(p, "IDLE.CHARACTER-ERROR", "A character with a parity error in idle is reported at once",
             "Table 8-1 16#080C (3964(R) clause); 3964r.md §8.1 item 4, §17 A13",
             "A character with a transmission error in idle raises 16#080C at once; a NAK after CDT is our reading (A13), silence is informational.",
             "character-error", "idle",
             [send_error("41", note="parity error"),
              expect(NAK, after="CDT", within="CDT + 2*CHAR", optional=True, absent_grade="informational",
                     note="NAK after CDT (A13)")],
             iut=(["16#080C"], ["16#0802"]), readings=["A13"], provenance="[S][O]"),
    ]
    return out
