"""The keys of an RK 512 profile, as the profile schema (:mod:`ptpcert.schema`) declares them:
the 3964R link's keys in ``[iut]`` (the character frame has 8 data bits, §2.3.2) and the
``[rk512]`` table: the link, T_RES, the roles the IUT plays, how it is made to request, and
what its memory offers (facts about the IUT, not parameters of the manual)."""

from __future__ import annotations

from dataclasses import replace

from ptpcert.procedures.p3964.link import LINK_SCHEMA
from ptpcert.schema import Key

from .model.params import INVALID_REQUESTS, LINKS, MEMORY_MODES, REQUEST_MODES, ROLES

_AREA = 65536
#: the shortest T_RES by baud rate (12-bit characters): 12 characters, the shortest response with
#: its handshake (model.params.shortest_response_ms gives it for the profile's character frame)
_SHORTEST_RESPONSE_MS = {b: -(-12 * 12 * 1000 // b) for b in (300, 600, 1200, 2400, 4800, 9600, 19200)}

SCHEMA: tuple[Key, ...] = tuple(
    replace(k, choices=(8,), doc=k.doc + " (8 for RK 512, §2.3.2)") if k.name == "data_bits" else k
    for k in LINK_SCHEMA) + (
    Key("link", "rk512", "choice", "the procedure below RK 512: 3964R (with BCC) or 3964 (without; open "
        "point AMB-27)", ref="Table 2-3", default="3964R", choices=LINKS),
    Key("response_time_ms", "rk512", "int", "T_RES, the response monitoring time of both sides; left out: "
        "10 s, the CP 341's value, and cases whose outcome hinges on T_RES also accept the figures' shorter "
        "5 s (7 s, 10 s) (AMB-02); at least the time the shortest response takes on the line", ref="§2.2.3 "
        "'response monitoring time'; Figs. 2-18, 2-19", default=None, lo=10, hi=3_600_000, unit="ms",
        floor=("baud_rate", _SHORTEST_RESPONSE_MS)),
    Key("roles", "rk512", "subset", "the roles the IUT can be tested in: passive (it serves SEND and FETCH), "
        "active (it issues them)", ref="§2.2.3", default=list(ROLES), choices=ROLES),
    Key("requests", "rk512", "choice", "how a tester makes the IUT request: by a request script handed to its "
        "command ({requests}), or not at all", default="script", choices=REQUEST_MODES),
    Key("memory", "rk512", "choice", "what the IUT's memory holds at start: the pattern of the reference "
        "(data can be checked), or unknown", default="pattern", choices=MEMORY_MODES),
    Key("db_range", "rk512", "pair", "the DB numbers that exist", ref="§6.3.2 Table 6-5",
        default=[1, 199], lo=1, hi=255, size=(2, 2)),
    Key("dx_range", "rk512", "pair", "the DX numbers that exist ([] for none)", ref="§6.3.2 Table 6-5",
        default=[1, 199], lo=1, hi=255, size=(0, 2)),
    Key("db_bytes", "rk512", "int", "the size of every DB and DX", default=512, lo=2, hi=_AREA, step=2,
        unit="bytes"),
    Key("byte_area_bytes", "rk512", "int", "the size of the flag, input and output areas", default=256,
        lo=1, hi=_AREA, unit="bytes"),
    Key("cell_area_cells", "rk512", "int", "the number of timers and of counters (2 bytes each)",
        default=256, lo=1, hi=_AREA // 2),
    Key("cell_fetch_limit_bytes", "rk512", "int", "the most bytes of timers or counters a partner's FETCH is "
        "served (a CP 341: 32); a longer one is refused (16#0608, REATEL 34h or 0Ch); left out: either is "
        "accepted (AMB-20)", ref="§6.3.2 'Providing data'", default=None, lo=2, hi=1024, step=2, unit="bytes"),
    Key("serves_dx_fetch", "rk512", "bool", "whether a partner's FETCH from a DX is served (a CP 341 lists "
        "no DX source) or refused; left out: either is accepted (AMB-20)", ref="§6.3.2 Table 6-10",
        default=None),
    Key("inexpressible_requests", "rk512", "subset", "the invalid requests the IUT's request interface cannot "
        "even express (a typed API that refuses them before they become requests): len-1025, len-0 (LEN over "
        "1024, of 0), db-0, flag-bit-8, cpu-5, send-to-flags; their local-check cases are unsupported",
        ref="§6.3.2 Tables 6-4 to 6-6; Table 8-1 class 05; Table 8-2 16#1E41", default=[],
        choices=INVALID_REQUESTS, size=(0, len(INVALID_REQUESTS)), when={"requests": ("script",)}),
)
