"""The model's two errors, shared by every procedure's stations and parameters."""

from __future__ import annotations

from typing import Any


class ParameterError(ValueError):
    """An invalid parameter value. ``name`` is the parameter, ``value`` what was given."""

    def __init__(self, name: str, value: Any, allowed: str):
        self.name, self.value, self.allowed = name, value, allowed
        super().__init__(f"{name} = {value!r} is not allowed: {allowed}")


class ModelError(RuntimeError):
    """A station was driven in a way the model does not allow (a harness bug)."""
