"""Building blocks of the RK 512 model tests: stations wired over the 3964R link model."""

from __future__ import annotations

from ptpcert.model.events import Delivered, Status
from ptpcert.model.link import Link
from ptpcert.procedures.p3964.model.params import Params3964
from ptpcert.procedures.p3964.model.station import Station3964
from ptpcert.procedures.rk512.model import RequestResult, Rk512Params, Rk512Station, Served
from ptpcert.procedures.rk512.model.readings import RK512_READINGS


def params(prio: str, baud=9600, proc="3964R", **kw) -> Rk512Params:
    return Rk512Params(link=proc, line=Params3964(procedure=proc, priority=prio, baud_rate=baud), **kw)


def settle(link: Link) -> Link:
    link.power_on(0.0)
    link.run_until_quiet(1.0)
    link.wire.clear()
    link.events.clear()
    return link


def pair(baud=9600, proc="3964R", ra=RK512_READINGS, rb=RK512_READINGS, a_kw=None, b_kw=None, **kw):
    """Two RK 512 stations: ``a`` (high priority) and ``b`` (low), powered up, quiet."""
    a = Rk512Station(params("high", baud, proc, **{**kw, **(a_kw or {})}), ra, name="a")
    b = Rk512Station(params("low", baud, proc, **{**kw, **(b_kw or {})}), rb, name="b")
    return settle(Link(a, b)), a, b


def with_tester(baud=9600, proc="3964R", readings=RK512_READINGS, tester_prio="low", **kw):
    """An RK 512 station ``a`` and a bare 3964(R) station ``t`` (the tester: it sends the
    frames a test crafts and delivers what ``a`` sends, answering nothing by itself)."""
    a = Rk512Station(params("high" if tester_prio == "low" else "low", baud, proc, **kw), readings, name="a")
    t = Station3964(Params3964(procedure=proc, priority=tester_prio, baud_rate=baud), name="t")
    return settle(Link(a, t)), a, t


def wire(link: Link) -> list[tuple[str, int]]:
    return [(w.src, w.byte) for w in link.wire]


def of(link: Link, st, cls):
    return [e for n, e in link.events if n == st.name and isinstance(e, cls)]


def results(link, st) -> list[RequestResult]:
    return of(link, st, RequestResult)


def codes(link, st, side=None) -> list[int]:
    return [e.code for e in of(link, st, Status) if side is None or e.side == side]


def delivered(link, st) -> list[bytes]:
    return [e.payload for e in of(link, st, Delivered)]


def served(link, st) -> list[Served]:
    return of(link, st, Served)


def run_until_delivered(link: Link, t: Station3964, n: int, limit: float = 100.0) -> list[bytes]:
    """Run until the tester has received ``n`` blocks in all."""
    end = link.now + limit
    while len(delivered(link, t)) < n:
        nt = link.next_time()
        assert nt <= end, f"the tester received {len(delivered(link, t))} of {n} blocks"
        link.run_until(nt)
    return delivered(link, t)


def run_until(link: Link, predicate, limit: float = 100.0) -> None:
    """Run the link step by step until ``predicate()`` holds."""
    end = link.now + limit
    while not predicate():
        nt = link.next_time()
        assert nt <= end, "the condition was not reached"
        link.run_until(nt)
