"""Reference model of the CP 341 ASCII driver (§2.2.4): parameters, readings of the open
points, the transition tables, the sans-IO station and its application. Standard library
only; no clocks, no I/O."""

import importlib as _importlib

# Each name is loaded from its module on first use (PEP 562), so that a program that needs
# only the parameters or the codec (the 3964R reference IUT, whose command line knows every
# procedure's options) does not pay for the station and its tables at start-up.
_WHERE = {
    "codec": None, "events": None, "records": None, "table": None,
    "APPS": "app", "AsciiHost": "app",
    "Piece": "codec", "char_name": "codec", "describe": "codec", "send_bytes": "codec",
    "split_frames": "codec",
    "FrameDiscarded": "events", "FrameStored": "events",
    "AsciiParams": "params",
    "READINGS": "readings", "AsciiReadings": "readings",
    "AsciiJob": "records", "SignalRecord": "records", "TxRecord": "records", "Why": "records",
    "AsciiStation": "station", "Timer": "station",
}


def __getattr__(name: str):
    if name not in _WHERE:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    where = _WHERE[name]
    module = _importlib.import_module(f".{where or name}", __name__)
    value = module if where is None else getattr(module, name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(_WHERE))


__all__ = [
    "codec", "events", "records", "table", "APPS", "AsciiHost", "Piece", "char_name", "describe",
    "send_bytes", "split_frames", "FrameDiscarded", "FrameStored", "AsciiParams", "READINGS",
    "AsciiReadings", "AsciiJob", "AsciiStation", "SignalRecord", "Timer", "TxRecord", "Why",
]
