"""Whether a case fits the IUT's response monitoring time at its baud rate.

T_RES runs on the requester from the acknowledgement of its (continuation) command until
the response has arrived, and on the responder from its non-final response until the
continuation command has arrived (§2.2.3 "Response message frame", Figs. 2-18, 2-19; where
exactly it starts and stops is open point AMB-17: here from the block's end to the other
block's end, the longer reading). A case whose frames cannot cross the line within the
shortest T_RES the IUT may have (a 138-byte block takes 5 s at 300 bit/s; a T_RES of 100 ms
is shorter than one at 9600 bit/s) would fail a correct IUT: it is unsupported, with the
figures. Pauses the case makes count too, except those written in terms of TRES that reach
the shortest T_RES: they let a T_RES run out on purpose (their case expects that).

Pure: the case's expanded steps and the parameters in, a reason or None out.
"""

from __future__ import annotations

from ptpcert.procedures.p3964.model import codec
from ptpcert.scenario import names_in

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


def tres_shortfall(steps, params, env: dict[str, float]) -> str | None:
    """Why the steps cannot run within the IUT's T_RES (``TRES_MIN`` of ``env``), or None."""
    limit = env["TRES_MIN"]
    char = params.char_time
    proc = params.procedure
    t = 0.0
    waiting: dict[str, float] = {}      # "iut" -> since when its request waits for a response
    owed: dict[str, float] = {}         # "iut" -> since when it waits for a continuation command
    served: dict[str, list[int]] = {}   # side -> [bytes asked for, responses sent] of its open passive request
    worst = (0.0, "")

    def over(since: float, what: str) -> None:
        nonlocal worst
        if t - since > worst[0]:
            worst = (t - since, what)

    for s in steps:
        if s.kind in ("wait", "silence", "break"):
            d = s.duration.eval(env)
            if d >= limit and "TRES" in names_in(s.duration):   # lets a T_RES run out on purpose
                waiting.clear()
                owed.clear()
            else:
                t += d
            continue
        if s.kind not in ("send", "expect"):
            continue
        if s.kind == "send":
            t += max(s.at.eval(env), 0.0)
        else:
            t += max(s.after.eval(env), 0.0)
        longest = max([len(s.data)] + [len(a) for a in s.alternatives])
        t += longest * char
        frame = _frame(s.data, proc)
        if frame is None or len(frame) < 4 or frame[0] not in (0x00, 0xFF) or frame[1] != 0x00:
            continue
        side, other = ("tester", "iut") if s.kind == "send" else ("iut", "tester")
        if frame[2] == 0x00:            # a response of ``side`` to ``other``'s command
            if other in waiting:
                over(waiting.pop(other), "the response the IUT waits for")
            req = served.get(side)
            if req is not None:
                req[1] += 1
                if side == "iut" and frame[3] == 0x00 and req[0] > _CHUNK * req[1]:
                    owed[side] = t + char  # after the requester's DLE
                else:
                    served.pop(side)
        elif frame[2] in _COMMANDS:     # a command of ``side``
            if frame[0] == 0xFF:
                if other in owed:
                    over(owed.pop(other), "the continuation the IUT waits for")
            else:
                owed.pop(other, None)
                served[other] = [_total(frame), 0]
            if side == "iut":           # the tester has no T_RES of its own: it follows its script
                waiting[side] = t + char    # from the responder's DLE
    need, what = worst
    if not what or need + 2 * char <= limit:
        return None
    baud = params.line.baud_rate
    return (f"{what} takes {1000 * need:.0f} ms on the line at {baud or 'the line rate of'} bit/s, "
            f"more than the IUT's T_RES of {1000 * limit:.0f} ms (§2.2.3 Figs. 2-18, 2-19): the case cannot "
            f"be run within it")
