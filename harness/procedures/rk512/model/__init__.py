"""The RK 512 computer link (CP 341 manual §2.2.3, §6.3.2, §8.3/8.4): a layer over the
3964(R) station. Pure codec, parameters, the partner CPU's memory, request scripts, the
readings of the open points, the two transition tables, the link-less core, the station,
its application and an ideal frame link. Standard library only; no clocks, no I/O."""

from . import codec, table
from .app import Rk512Host, parse_cf_set
from .codec import Area, Header, Kind, classify, describe, status_for_reatel
from .core import Rk512Core
from .events import FrameNotSent, FrameReceived, FrameSent, Ready, RequestResult, Served, Wakeup, interface_lines
from .framelink import FrameLink
from .memory import Memory
from .params import Rk512Params, default_response_time_ms, figure_response_time_ms
from .readings import RK512_READINGS, Rk512Readings
from .requests import Request, ScriptError, Wait, parse_line, parse_request, parse_script
from .station import Rk512Station

__all__ = [
    "codec", "table", "Rk512Host", "parse_cf_set", "Area", "Header", "Kind", "classify", "describe",
    "status_for_reatel", "Rk512Core", "FrameNotSent", "FrameReceived", "FrameSent", "Ready",
    "RequestResult", "Served", "Wakeup", "interface_lines", "FrameLink", "Memory", "Rk512Params",
    "default_response_time_ms", "figure_response_time_ms", "RK512_READINGS", "Rk512Readings", "Request", "ScriptError", "Wait",
    "parse_line", "parse_request", "parse_script", "Rk512Station",
]
