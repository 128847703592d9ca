"""The simplest application above a station: what it does with delivered blocks.

``echo`` submits every received (non-empty) block as a new send job, as the bundled
reference implementation does; ``none`` only consumes them. Any station with
``pop_events()``, ``request_send(now, payload)`` and ``now`` can sit below it (a procedure
with a richer application, RK 512's request script or ASCII's reading pace, has its own).
Pure, like the station.
"""

from __future__ import annotations

from typing import Any

from .events import Delivered, Event

APPS = ("echo", "none")


class Host:
    """A station plus its application; :meth:`drain` runs the application on the
    station's events and returns them all."""

    def __init__(self, station: Any, app: str = "echo"):
        if app not in APPS:
            raise ValueError(f"application {app!r}: allowed values are {', '.join(APPS)}")
        self.station = station
        self.app = app

    def drain(self, now: float | None = None) -> list[Event]:
        """The station's events; the application's new jobs are handed over at ``now``
        (default: the station's own time)."""
        st = self.station
        events = st.pop_events()
        if not events:
            return events           # nothing happened (most instants): nothing to run
        out: list[Event] = []
        at = st.now if now is None else now
        while events:
            out.extend(events)
            if self.app == "echo":
                for e in events:
                    if isinstance(e, Delivered) and e.payload:
                        st.request_send(at, e.payload)
            events = st.pop_events()
        return out
