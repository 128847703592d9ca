"""Whether a case fits the IUT's response monitoring time at its baud rate.

T_RES runs on the requester from the acknowledgement of its (continuation) command until
the response has arrived, and on the responder from its non-final response until the
continuation command has arrived (§2.2.3 "Response message frame", Figs. 2-18, 2-19; where
exactly it starts and stops is open point AMB-17: here from the block's end to the other
block's end, the longer reading). A case whose frames cannot cross the line within the
shortest T_RES the IUT may have (a 138-byte block takes 5 s at 300 bit/s; a T_RES of 100 ms
is shorter than one at 9600 bit/s) would fail a correct IUT: it is unsupported, with the
figures. Only the line's time counts: a pause a case makes inside a T_RES is its own, derived
from T_RES (``TRES_MIN``), and one that outlasts T_RES is meant to. A block refused by NAK
neither starts nor stops a T_RES (AMB-17: it runs from the DLE that takes the command).

Pure: the case's expanded steps and the parameters in, a reason or None out.
"""

from __future__ import annotations

from ptpcert.procedures.p3964.model import codec

_COMMANDS = (0x41, 0x4F, 0x45)     # 'A', 'O', 'E' (Table 2-1)
_WORD_TYPES = (0x44, 0x58, 0x54, 0x5A)  # D, X, T, Z count words (Table 2-1)
_CHUNK = 128


def _frame(data: bytes, procedure: str) -> bytes | None:
    if len(data) < 3:
        return None
    try:
        return codec.parse_body(data, procedure)
    except (codec.FrameError, ValueError, IndexError):
        return None


def _total(cmd: bytes) -> int:
    """The bytes a first command asks for (its length field in its unit)."""
    if len(cmd) < 8:
        return 0
    n = (cmd[6] << 8) | cmd[7]
    return 2 * n if cmd[3] in _WORD_TYPES else n


def _acknowledged(steps, i: int) -> bool:
    """The block of step ``i`` was taken: the next step of the other side is a lone DLE."""
    other = "send" if steps[i].kind == "expect" else "expect"
    for s in steps[i + 1:]:
        if s.kind == other:
            return s.data == bytes([codec.DLE])
        if s.kind in ("send", "expect"):
            return False
    return False


def tres_shortfall(steps, params, env: dict[str, float]) -> str | None:
    """Why the steps cannot run within the IUT's T_RES (``TRES_MIN`` of ``env``), or None."""
    limit = env["TRES_MIN"]
    char = params.char_time
    proc = params.procedure
    steps = list(steps)
    t = 0.0
    waiting: float | None = None        # since when the IUT's request waits for its response
    owed: float | None = None           # since when the IUT waits for the tester's continuation
    served: list[int] | None = None     # [bytes asked for, responses sent] of the tester's open request
    worst = (0.0, "")

    def over(since: float, what: str) -> None:
        nonlocal worst
        if t - since > worst[0]:
            worst = (t - since, what)

    for i, s in enumerate(steps):
        if s.kind not in ("send", "expect"):
            continue            # pauses are the case's own, derived from T_RES where they matter
        t += max([len(s.data)] + [len(a) for a in s.alternatives]) * char
        frame = _frame(s.data, proc)
        if frame is None or len(frame) < 4 or frame[0] not in (0x00, 0xFF) or frame[1] != 0x00:
            continue
        if not _acknowledged(steps, i):
            continue            # refused by NAK or cut short: not received, T_RES neither starts nor stops
        from_iut = s.kind == "expect"
        if frame[2] == 0x00:    # a response
            if not from_iut and waiting is not None:
                over(waiting, "the response the IUT waits for")
                waiting = None
            if from_iut and served is not None:
                served[1] += 1
                if frame[3] == 0x00 and served[0] > _CHUNK * served[1]:
                    owed = t + char     # from the tester's DLE
                else:
                    served = None
        elif frame[2] in _COMMANDS:
            if from_iut:
                waiting = t + char      # from the tester's DLE (AMB-17: T_RES starts when it is taken)
            elif frame[0] == 0xFF:
                if owed is not None:
                    over(owed, "the continuation the IUT waits for")
                    owed = None
            else:               # a first command where a continuation may be due ends that wait too
                if owed is not None:
                    over(owed, "the command the IUT waits for")
                owed = None
                served = [_total(frame), 0]
    need, what = worst
    if not what or need + 2 * char <= limit:
        return None
    baud = params.line.baud_rate
    return (f"{what} takes {1000 * need:.0f} ms on the line at {baud or 'the line rate of'} bit/s, "
            f"more than the IUT's T_RES of {1000 * limit:.0f} ms (§2.2.3 Figs. 2-18, 2-19): the case cannot "
            f"be run within it")
