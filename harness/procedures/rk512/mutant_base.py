"""What the broken variants of the RK 512 reference (:mod:`.mutants`, :mod:`.mutants_rules`)
share: their registry (``MUTANTS``, filled by the ``@mutant`` registrar of
:mod:`ptpcert.variants`) and the kinds of change they make: frames changed on their way to
the link (:class:`Rewrite`), the application's requests changed (:class:`RequestChange`), a
broken 3964(R) link under a correct RK 512 layer (:class:`LinkMutant`)."""

from __future__ import annotations

from ptpcert.procedure import Mutant
from ptpcert.procedures.rk512.model import Rk512Station
from ptpcert.procedures.rk512.model.requests import Request, parse_line
from ptpcert.variants import registrar

MUTANTS: dict[str, Mutant] = {}


mutant = registrar(MUTANTS, prefix="Rk512Mutant_")


class Rewrite(Rk512Station):
    """A station whose frames are changed on their way to the link."""

    def rewrite(self, frame: bytes, origin: str, owner) -> bytes:
        return frame

    def _queue(self, frame, origin, owner, detail=""):
        super()._queue(self.rewrite(bytes(frame), origin, owner), origin, owner, detail)


class RequestChange(Rk512Station):
    """A station whose application's requests are changed before the station takes them."""

    def change(self, req: Request) -> Request:
        return req

    def request(self, now, req):
        if isinstance(req, str):
            req = parse_line(req)
        return super().request(now, self.change(req) if isinstance(req, Request) else req)


class LinkMutant(Rk512Station):
    """A correct RK 512 layer over the broken 3964(R) link ``LINK`` (a variant of
    :mod:`ptpcert.procedures.p3964.mutants`)."""

    LINK = ""

    def __init__(self, params, *a, name: str = "station", **kw):
        super().__init__(params, *a, name=name, **kw)
        from ptpcert.procedures.p3964.mutants import MUTANTS as LINK_MUTANTS
        self.link = LINK_MUTANTS[self.LINK].make(self.params.line, name=name)
