"""Start-up (Fig. 2-9; §2.2.2 Receive, Note)."""

from ._build import NAK, case, expect, receive_block, silence


def cases(p):
    return [
        case(p, "STARTUP.ONE-NAK", "At start-up the IUT sends exactly one NAK",
             "Fig. 2-9 'send NAK'; §2.2.2 Receive, Note",
             "After initialising its interface the procedure sends one NAK, so that the partner goes to idle, and nothing more.",
             "start-up", "idle",
             [expect(NAK, within="STARTUP", note="the start-up NAK"),
              silence("ADT + CDT", note="one NAK only")],
             start="power-on", requires=["restart"], provenance="[S][F]", rules=["3964.START.NAK"]),
        case(p, "STARTUP.THEN-IDLE", "After its start-up NAK the IUT is idle and receives a block",
             "Fig. 2-9; Fig. 2-11 'wait (idle)'",
             "After the start-up NAK the procedure is idle: a STX is answered with DLE.",
             "start-up", "receiver",
             [expect(NAK, within="STARTUP", note="the start-up NAK")] + receive_block(b"\x31\x32", p),
             start="power-on", requires=["restart"], delivered=[b"\x31\x32"], echo_after=[b"\x31\x32"],
             provenance="[F][I]", rules=["3964.START.IDLE"]),
    ]
