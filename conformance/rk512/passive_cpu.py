"""The IUT passive, the state of its CPU (§6.3.2 "Using interprocessor communication
flags"; §7.3; §8.3 Table 8-1 16#060D, 16#060F; Table 8-3): P-11 (coordination flags), P-12
(CPU in STOP). Both need a set-up of the profile ([iut.setups])."""

import math

from ._build import case, header, line_chars, prime, receive, resp, seq_data, wait

#: how long the application keeps the flag set, at least: it must outlast the exchanges that
#: find it set, however slow the line (twice their time on the line, §2.2.2)
RESET_MS = 1000
FLAG = (12, 3)


def reset_ms(p, *frames) -> int:
    """The flag's reset time for a case whose ``frames`` must find it set: RESET_MS, or
    twice their time on the line (and 4 ADT for the handshakes) where that is longer,
    rounded up to 100 ms."""
    need = 2 * (line_chars(p, *frames) * p.char_time + 4 * p.adt)
    return max(RESET_MS, 100 * math.ceil(need * 10))


def cases(c):
    p = c.p
    w = c.db_w
    if p.byte_area_bytes <= FLAG[0]:
        return []
    b9, b10 = FLAG[0], 0x10 | FLAG[1]
    send_cf = header("A", "D", w, 0, 2, b9=b9, b10=b10) + seq_data(4)
    fetch_cf = header("E", "D", c.db, 0, c.fw, b9=b9, b10=b10)
    hold = reset_ms(p, send_cf, resp(0x32), fetch_cf, resp(0x32))
    flag = {"name": "flag_set", "flag": f"{FLAG[0]}.{FLAG[1]}", "reset_ms": hold}
    out = [
        case(c, "P-11.FLAG-SET-REFUSES", f"Coordination flag {FLAG[0]}.{FLAG[1]} is set: SEND and FETCH naming it get 32h",
             "§6.3.2 'Using interprocessor communication flags'; §8.3 Table 8-1 16#060F; Table 8-3 (32h)",
             "While the coordination flag named in bytes 9/10 is set the responder refuses the request with REATEL 32h (16#060F), nothing moved.",
             "passive-cpu", "receiver",
             [prime(send_cf), receive(resp(0x32)), prime(fetch_cf), receive(resp(0x32))],
             iut=(["16#060F"], []), setup=("flag_set", {k: v for k, v in flag.items() if k != "name"}),
             needs={"db": [w, c.db], "db_bytes": 4}, readings=["AMB-07"], provenance="[S][I]"),
        case(c, "P-11.FLAG-RESET-ALLOWS", "Once the flag is reset the SEND goes through, and the IUT sets the flag again",
             "§6.3.2 'Using interprocessor communication flags'; §8.3 Table 8-1 16#060F",
             "After the user program resets the flag a request naming it is served; the transfer sets the flag, so a second one at once gets 32h.",
             "passive-cpu", "receiver",
             [wait(f"{hold + 200}ms", note="the application resets the flag"), prime(send_cf), receive(resp(0)),
              prime(send_cf), receive(resp(0x32), alternatives=[resp(0)], alt_grade="informational",
                                      note="the flag set by the transfer (a reading) refuses it")],
             iut=((), ["16#060F"]), setup=("flag_set", {k: v for k, v in flag.items() if k != "name"}),
             needs={"db": [w], "db_bytes": 4}, readings=["AMB-07", "AMB-08"], provenance="[S][I]"),
        case(c, "P-12.CPU-STOP", "The partner CPU in STOP: every SEND and FETCH gets 2Ah",
             "§7.3; §8.3 Table 8-1 16#060D; Table 8-3 (2Ah)",
             "A command that arrives while the CPU is in STOP is refused with REATEL 2Ah (16#060D).",
             "passive-cpu", "receiver",
             [prime(header("A", "D", w, 0, 2) + seq_data(4)), receive(resp(0x2A)),
              prime(header("E", "D", c.db, 0, c.fw)), receive(resp(0x2A))],
             iut=(["16#060D"], []), setup=("cpu_stop", {}), needs={"db": [w, c.db], "db_bytes": 4}, provenance="[S]"),
    ]
    return out
