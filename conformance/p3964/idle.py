"""Idle (§2.2.2 Receive/setup; Fig. 2-11; Table 8-1 16#0802, 16#080C)."""

from ._build import NAK, case, expect, nak_after_cdt, receive_block, send, send_error, silence

STRAY_REF = "§2.2.2 Receive/setup; Fig. 2-11 'any characters except STX or NAK'; Table 8-1 16#0802"


def cases(p):
    out = [
        case(p, "IDLE.NAK-IGNORED", "A NAK received in idle is ignored", "§2.2.2 Receive/setup",
             "A station in idle gives no answer and raises no error for a NAK.",
             "idle", "idle", [send(NAK, note="NAK"), silence("2*CDT + ADT", note="no answer")],
             provenance="[S]", rules=["3964.IDLE.NAK-IGNORED"]),
    ]
    for value, name in ((0x41, "CHARACTER"), (0x10, "DLE"), (0x03, "ETX"), (0x00, "NUL")):
        out.append(case(
            p, f"IDLE.STRAY-{name}", f"A stray {name} ({value:02X}) in idle gets a NAK after CDT of quiet", STRAY_REF,
            "Any character other than STX or NAK received in idle is answered with NAK once the character delay time has expired (16#0802), not before.",
            "idle", "idle", [send(bytes([value]), note="a stray character"), nak_after_cdt()],
            iut=(["16#0802"], ()), provenance="[S]", rules=["3964.IDLE.STRAY-NAK"]))
    out += [
        case(p, "IDLE.STRAY-THEN-BLOCK", "After answering a stray character the IUT receives the next block",
             STRAY_REF + "; Fig. 2-11 'STX received'",
             "The NAK for a stray character returns the procedure to idle, where STX starts a reception.",
             "idle", "receiver",
             [send("41"), nak_after_cdt()] + receive_block(b"\x51", p),
             iut=(["16#0802"], ()), delivered=[b"\x51"], echo_after=[b"\x51"], provenance="[S][I]",
             rules=["3964.IDLE.STRAY-NAK", "3964.RX.SETUP-DLE"]),
        case(p, "IDLE.QUIET-RESTARTS", "Two stray characters half a CDT apart get one NAK",
             STRAY_REF,
             "Further stray characters during the quiet wait start it again (A7), so two characters get one NAK, once the line has been quiet for CDT; a wait that is not restarted ends CDT after the first (also accepted), never earlier.",
             "idle", "idle",
             [send("41", note="a stray character"), send("42", at="0.5*CDT", note="another, half a CDT later"),
              expect(NAK, after="0.5*CDT", within="CDT + 2*CHAR",
                     note="one NAK: CDT after the second (A7), or CDT after the first")],
             iut=(["16#0802"], ()), readings=["A7"], provenance="[S][I]", rules=["3964.IDLE.QUIET-RESTARTS"]),
        case(p, "IDLE.CHARACTER-ERROR", "A character with a parity error in idle is reported; a NAK after CDT is our reading",
             "Table 8-1 16#080C (3964(R): reported at once in idle); §2.2.2 Receive/setup",
             "A character with a transmission error in idle raises 16#080C; a NAK after CDT is our reading (A13), silence is informational.",
             "character-error", "idle",
             [send_error("41", note="parity error"),
              expect(NAK, after="CDT", within="CDT + 2*CHAR", optional=True, absent_grade="informational",
                     note="NAK after CDT (A13)")],
             iut=(["16#080C"], ["16#0802"]), readings=["A13"], provenance="[S][O]",
             rules=["3964.IDLE.CHARACTER-ERROR"]),
        case(p, "IDLE.CORRUPTED-STX", "A STX with a parity error in idle is not answered with DLE",
             "Fig. 2-11 'STX received'; Table 8-1 16#080C",
             "A character with a transmission error is never taken for STX: no DLE follows it (a NAK after CDT is our reading, A13).",
             "character-error", "idle",
             [send_error("02", note="STX with a parity error"),
              expect(NAK, after="CDT", within="CDT + 2*CHAR", optional=True, absent_grade="informational",
                     note="no DLE; NAK after CDT (A13) or nothing")],
             iut=(["16#080C"], ["16#0802"]), readings=["A13"], provenance="[I]",
             rules=["3964.IDLE.CORRUPTED-STX"]),
    ]
    return out
