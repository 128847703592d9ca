"""The IUT profile: a TOML file describing the implementation under test, like a protocol
conformance statement. Parameters, how it can be made to send, which line conditions it
reads, whether it reports STATUS, and the failures expected with their reasons.

```toml
[iut]
procedure = "3964R"              # "3964" | "3964R"
priority = "low"                 # the IUT's own: "low" | "high"
character_delay_ms = 20
acknowledgement_delay_ms = 20
setup_attempts = 6
transmission_attempts = 6
baud_rate = 9600                 # default 9600
data_bits = 8                    # default 8
parity = "even"                  # default "even"
stop_bits = 1                    # default 1
send_trigger = "echo"            # "echo": sends back every block it receives; "none"
line_conditions = "parmrk"       # "parmrk": reads PARMRK marks on exec:/pty:; "none"
status_from_stderr = true        # prints "STATUS 16#XXXX" lines on stderr

[expected_failures]
"3964R.D08.DLE-OTHER" = "known bug #12: NAK sent at once"
```
"""

from __future__ import annotations

import tomllib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from .model.params import BAUD_RATES, ParameterError, Params3964

REQUIRED = ("procedure", "priority", "character_delay_ms", "acknowledgement_delay_ms",
            "setup_attempts", "transmission_attempts", "send_trigger", "line_conditions",
            "status_from_stderr")
DEFAULTS = {"baud_rate": 9600, "data_bits": 8, "parity": "even", "stop_bits": 1}
CHOICES = {
    "procedure": ("3964", "3964R"),
    "priority": ("low", "high"),
    "send_trigger": ("echo", "none"),
    "line_conditions": ("parmrk", "none"),
    "parity": ("none", "odd", "even"),
}
_PARAM_OF = {"character_delay_ms": "cdt_ms", "acknowledgement_delay_ms": "adt_ms"}
_KEY_OF = {v: k for k, v in _PARAM_OF.items()}


class ProfileError(ValueError):
    def __init__(self, path: str, key: str, message: str):
        self.path, self.key = path, key
        super().__init__(f"{path}: {key}: {message}" if key else f"{path}: {message}")


@dataclass(frozen=True)
class Profile:
    params: Params3964
    send_trigger: str = "echo"
    line_conditions: str = "parmrk"
    status_from_stderr: bool = True
    expected_failures: dict[str, str] = field(default_factory=dict)
    path: str = ""

    @property
    def echo(self) -> bool:
        return self.send_trigger == "echo"

    def to_dict(self) -> dict[str, Any]:
        p = self.params
        return {
            "procedure": p.procedure, "priority": p.priority,
            "character_delay_ms": p.cdt_ms, "acknowledgement_delay_ms": p.adt_ms,
            "setup_attempts": p.setup_attempts, "transmission_attempts": p.transmission_attempts,
            "baud_rate": p.baud_rate, "data_bits": p.data_bits, "parity": p.parity,
            "stop_bits": p.stop_bits, "send_trigger": self.send_trigger,
            "line_conditions": self.line_conditions, "status_from_stderr": self.status_from_stderr,
            "expected_failures": dict(self.expected_failures),
        }


def load_profile(path: str | Path) -> Profile:
    path = Path(path)
    where = str(path)
    try:
        raw = tomllib.loads(path.read_text("utf-8"))
    except FileNotFoundError:
        raise ProfileError(where, "", "no such file") from None
    except OSError as exc:
        raise ProfileError(where, "", f"cannot be read: {exc.strerror}") from None
    except tomllib.TOMLDecodeError as exc:
        raise ProfileError(where, "", f"not valid TOML: {exc}") from None
    return profile_from_dict(raw, where)


def profile_from_dict(raw: dict[str, Any], where: str = "<profile>") -> Profile:
    unknown_tables = sorted(set(raw) - {"iut", "expected_failures"})
    if unknown_tables:
        raise ProfileError(where, unknown_tables[0], "unknown table or key (allowed: [iut], [expected_failures])")
    iut = raw.get("iut")
    if not isinstance(iut, dict):
        raise ProfileError(where, "iut", "missing table [iut]")
    allowed = set(REQUIRED) | set(DEFAULTS)
    for key in iut:
        if key not in allowed:
            raise ProfileError(where, f"iut.{key}", "unknown key (allowed: " + ", ".join(sorted(allowed)) + ")")
    for key in REQUIRED:
        if key not in iut:
            hint = f"one of {', '.join(CHOICES[key])}" if key in CHOICES else "required"
            raise ProfileError(where, f"iut.{key}", f"missing ({hint})")
    values = {**DEFAULTS, **iut}
    for key, choices in CHOICES.items():
        if values[key] not in choices:
            raise ProfileError(where, f"iut.{key}", f"{values[key]!r} is not allowed; allowed values: "
                               + ", ".join(f'"{c}"' for c in choices))
    if not isinstance(values["status_from_stderr"], bool):
        raise ProfileError(where, "iut.status_from_stderr", f"{values['status_from_stderr']!r}: must be true or false")
    if values["baud_rate"] not in BAUD_RATES:
        raise ProfileError(where, "iut.baud_rate", f"{values['baud_rate']!r} is not allowed; allowed values: "
                           + ", ".join(map(str, BAUD_RATES)))
    try:
        params = Params3964(
            procedure=values["procedure"], priority=values["priority"],
            cdt_ms=values["character_delay_ms"], adt_ms=values["acknowledgement_delay_ms"],
            setup_attempts=values["setup_attempts"],
            transmission_attempts=values["transmission_attempts"],
            baud_rate=values["baud_rate"], data_bits=values["data_bits"],
            parity=values["parity"], stop_bits=values["stop_bits"],
        )
    except ParameterError as exc:
        key = _KEY_OF.get(exc.name, exc.name)
        raise ProfileError(where, f"iut.{key}", str(exc).replace(exc.name, key, 1)) from None
    xf = raw.get("expected_failures", {})
    if not isinstance(xf, dict) or any(not isinstance(v, str) or not v.strip() for v in xf.values()):
        raise ProfileError(where, "expected_failures", "a table of case id = \"reason\" (each with a reason)")
    return Profile(params, values["send_trigger"], values["line_conditions"],
                   values["status_from_stderr"], dict(xf), where)


def reference_profile(**overrides: Any) -> Profile:
    """The profile matching ``ptpcert iut`` with the given options (tests, self-checks)."""
    base = dict(procedure="3964R", priority="low", character_delay_ms=20,
                acknowledgement_delay_ms=20, setup_attempts=6, transmission_attempts=6,
                send_trigger="echo", line_conditions="parmrk", status_from_stderr=True)
    base.update(overrides)
    xf = base.pop("expected_failures", {})
    return profile_from_dict({"iut": base, "expected_failures": xf})
