"""The RK 512 model follows the model conventions: standard library, ptpcert.model and the
3964R link's model only
(no clocks, threads, I/O, hypothesis), public methods with ``now``, frozen events."""

import ast
import dataclasses
import inspect
import sys
from pathlib import Path

import ptpcert.procedures.rk512.model as rk512
from ptpcert.procedures.rk512.model import events

PKG = Path(rk512.__file__).parent
FORBIDDEN = {"time", "threading", "select", "subprocess", "serial", "hypothesis", "logging", "socket",
             "asyncio", "os", "io", "random"}


def test_imports_are_stdlib_or_model():
    for path in PKG.glob("*.py"):
        tree = ast.parse(path.read_text())
        for node in ast.walk(tree):
            if isinstance(node, ast.Import):
                names = [a.name for a in node.names]
            elif isinstance(node, ast.ImportFrom):
                if node.level:       # relative: inside the RK 512 model
                    assert node.level <= 2, (path.name, node.module)
                    continue
                if node.module.startswith(("ptpcert.model", "ptpcert.procedures.p3964.model")):
                    continue
                names = [node.module]
            else:
                continue
            for name in names:
                top = name.split(".")[0]
                assert top in sys.stdlib_module_names and top not in FORBIDDEN, (path.name, name)


def test_events_are_frozen_dataclasses():
    for name in ("RequestResult", "Served", "FrameReceived", "FrameSent", "FrameNotSent", "Ready", "Wakeup"):
        cls = getattr(events, name)
        assert dataclasses.is_dataclass(cls) and cls.__dataclass_params__.frozen, name
        assert [f.name for f in dataclasses.fields(cls)][0] == "time", name


def test_public_methods_take_now():
    from ptpcert.procedures.rk512.model import Rk512Core, Rk512Station
    for cls in (Rk512Core, Rk512Station):
        for name in ("power_on", "request", "restart", "handle_timer", "frame_received", "frame_sent",
                     "frame_failed", "send_raw"):
            params = list(inspect.signature(getattr(cls, name)).parameters)
            assert params[1] == "now", (cls.__name__, name)
    for name in ("line_event", "request_send", "receive"):
        assert list(inspect.signature(getattr(Rk512Station, name)).parameters)[1] == "now"
