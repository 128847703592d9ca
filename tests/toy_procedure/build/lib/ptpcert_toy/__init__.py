"""The toy procedure's description: what ptpcert's core needs to know of it, and nothing of
ptpcert names it. ``[iut] procedure = "TOY"`` selects it; its own table is ``[toy]``."""

from __future__ import annotations

from importlib import resources
from typing import Any

from ptpcert.model.app import Host
from ptpcert.model.errors import ParameterError
from ptpcert.procedure import Procedure, ProcedureError

from .model import ToyParams, ToyStation

_LINE_KEYS = ("baud_rate",)
_TABLE_KEYS = ("reply_delay_ms",)


class ToyProcedure(Procedure):
    id = "toy"
    title = "Toy ENQ/ACK"
    names = ("TOY",)
    tables = ("toy",)
    groups = ("reply", "regression")
    time_names = ("RDT",)
    suite = "ptpcert_toy.cases"
    send_triggers = ("none",)
    rank = 1000

    # -- profiles and parameters
    def profile_keys(self) -> tuple[str, ...]:
        return _LINE_KEYS

    def params_from_profile(self, iut: dict[str, Any], tables: dict[str, dict[str, Any]]) -> ToyParams:
        table = tables.get("toy", {})
        for key in table:
            if key not in _TABLE_KEYS:
                raise ProcedureError(f"toy.{key}", f"unknown key (allowed: {', '.join(_TABLE_KEYS)})")
        try:
            return ToyParams(**{k: iut[k] for k in _LINE_KEYS if k in iut}, **table)
        except ParameterError as exc:
            where = "toy" if exc.name in _TABLE_KEYS else "iut"
            raise ProcedureError(f"{where}.{exc.name}", f"{exc.value!r} is not allowed: {exc.allowed}") from None

    def profile_dict(self, params: ToyParams) -> dict[str, Any]:
        return {"procedure": "TOY", "baud_rate": params.baud_rate, "reply_delay_ms": params.reply_delay_ms}

    def params_from_table(self, raw: dict[str, Any]) -> ToyParams:
        try:
            return ToyParams(**raw)
        except ParameterError as exc:
            raise ProcedureError(exc.name, str(exc)) from None
        except TypeError as exc:
            raise ProcedureError("", str(exc)) from None

    def params_table(self, params: ToyParams) -> dict[str, Any]:
        return {"reply_delay_ms": params.reply_delay_ms, "baud_rate": params.baud_rate}

    def param_names(self) -> frozenset[str]:
        return frozenset(("reply_delay_ms", "baud_rate"))

    def timer_env(self, params: ToyParams) -> dict[str, float]:
        return {"RDT": params.reply, "CHAR": params.char_time}

    def edge_timers(self, params: ToyParams) -> tuple[float, ...]:
        return (params.reply,)

    def reference_profile(self, **settings: Any):
        from ptpcert.profile import profile_from_dict
        iut = {"procedure": "TOY", "send_trigger": "none", "line_conditions": "none", "status_from_stderr": False}
        table = {k: settings.pop(k) for k in list(settings) if k in _TABLE_KEYS}
        iut.update(settings)
        return profile_from_dict({"iut": iut, "toy": table})

    # -- models
    def station(self, params: ToyParams, *, name: str = "iut", mutant: str | None = None,
                readings: Any = None, explain: bool = False) -> ToyStation:
        if mutant:
            raise ProcedureError("mutant", "the toy procedure has no broken variants")
        return ToyStation(params, name=name)

    def host(self, station: ToyStation, *, app: str = "none", vector: Any = None) -> Host:
        return Host(station, "none")

    def apps(self) -> tuple[str, ...]:
        return ("none",)

    def echo_time_limit(self, params: ToyParams, payloads: list[bytes]) -> float:
        return 1.0

    # -- ptpcert iut
    def add_iut_arguments(self, group) -> None:
        group.add_argument("--reply-delay-ms", type=int, default=20, help="TOY: the reply delay (default 20)")

    def params_from_iut(self, args) -> ToyParams:
        try:
            return ToyParams(reply_delay_ms=args.reply_delay_ms, baud_rate=args.baud)
        except ParameterError as exc:
            raise ProcedureError("", str(exc)) from None

    # -- its golden vectors ship with it
    def vectors_dir(self):
        return resources.files(__name__).joinpath("vectors")
