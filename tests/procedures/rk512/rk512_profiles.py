"""IUT profiles of RK 512 for the tests, and the reference IUT's command for each."""

from __future__ import annotations

import json
import sys
from pathlib import Path

from ptpcert.profile import profile_from_dict

PY = sys.executable
ROOT = Path(__file__).resolve().parents[3]
SETUPS = {"cpu_stop": "--cpu-stop", "flag_set": "--cf-set {flag}@{reset_ms}"}
#: large areas, so that every case of the suite (1024-byte requests of every type) applies
BIG = {"db_bytes": 2048, "byte_area_bytes": 2048, "cell_area_cells": 1024}


def rk_profile_dict(link="3964R", priority="low", *, cdt=20, adt=20, t_res=500, setups=True, **rk) -> dict:
    iut = dict(procedure="RK512", priority=priority, character_delay_ms=cdt, acknowledgement_delay_ms=adt,
               setup_attempts=6, transmission_attempts=6, send_trigger="none", line_conditions="parmrk",
               status_from_stderr=True)
    if setups:
        iut["setups"] = dict(SETUPS)
    table = {"link": link, "response_time_ms": t_res, **BIG, **rk}
    return {"iut": iut, "rk512": table}


def rk_profile(link="3964R", priority="low", **kw):
    return profile_from_dict(rk_profile_dict(link, priority, **kw))


def write_profile(path: Path, raw: dict) -> Path:
    """A profile dict as a TOML file (flat tables, lists and strings only)."""
    def val(v):
        return json.dumps(list(v) if isinstance(v, tuple) else v)
    lines = ["[iut]"]
    iut = dict(raw["iut"])
    setups = iut.pop("setups", {})
    lines += [f"{k} = {val(v)}" for k, v in iut.items()]
    lines += ["", "[rk512]"] + [f"{k} = {val(v)}" for k, v in raw["rk512"].items()]
    if setups:
        lines += ["", "[iut.setups]"] + [f"{k} = {val(v)}" for k, v in setups.items()]
    path.write_text("\n".join(lines) + "\n")
    return path


def iut_command(raw: dict, mutant: str | None = None, scheme: str = "exec") -> str:
    """The reference IUT (``ptpcert iut --procedure RK512``) for the profile, as an
    exec:/pty: URL with {requests}."""
    iut, rk = raw["iut"], raw["rk512"]
    cmd = (f"{PY} -m ptpcert.cli iut --procedure RK512 --link {rk['link']} --priority {iut['priority']} "
           f"--cdt-ms {iut['character_delay_ms']} --adt-ms {iut['acknowledgement_delay_ms']} "
           f"--response-time-ms {rk['response_time_ms']} --db-bytes {rk['db_bytes']} "
           f"--byte-area-bytes {rk['byte_area_bytes']} --cell-area-cells {rk['cell_area_cells']} --parmrk "
           "--requests {requests}" + (f" --mutant {mutant}" if mutant else ""))
    return f"exec:{cmd}" if scheme == "exec" else f"pty:{cmd} --port {{port}}"


#: the RK 512 station written by someone else from the manual alone (tests/independent/rk512)
INDEPENDENT = ROOT / "tests" / "independent" / "rk512" / "iut_rk512.py"


def independent_command(raw: dict, brk: str | None = None, scheme: str = "exec") -> str:
    """The independent RK 512 station for the profile, through exactly the interface of an RK 512
    IUT (request script in {requests}, the set-ups' words appended), as an exec:/pty: URL. It
    reads and writes the line on stdin/stdout, so over pty: the shell points both at {port}."""
    iut, rk = raw["iut"], raw["rk512"]
    cmd = (f"{PY} {INDEPENDENT} --link {rk['link']} --priority {iut['priority']} "
           f"--cdt-ms {iut['character_delay_ms']} --adt-ms {iut['acknowledgement_delay_ms']} "
           f"--setup-attempts {iut['setup_attempts']} --transmission-attempts {iut['transmission_attempts']} "
           f"--tres-ms {rk['response_time_ms']} --db-bytes {rk['db_bytes']} "
           f"--byte-area-bytes {rk['byte_area_bytes']} --cell-area-cells {rk['cell_area_cells']} --parmrk "
           "--requests {requests}" + (f" --break {brk}" if brk else ""))
    return f"exec:{cmd}" if scheme == "exec" else f"pty:{cmd} <{{port}} >{{port}}"


def independent_variants() -> dict[str, str]:
    """The independent station's broken variants: name -> the rule it breaks (``--list-breaks``)."""
    import subprocess
    out = subprocess.run([PY, str(INDEPENDENT), "--list-breaks"], capture_output=True, text=True, check=True).stdout
    return {line.split()[0]: line[len(line.split()[0]):].strip() for line in out.splitlines() if line.strip()}


def run_cases(url: str, profile, cases):
    """The cases (Vectors, already generated) run against ``url`` under ``profile``: the
    RunResult."""
    from ptpcert import results as R
    from ptpcert.runner import Runner, RunOptions
    from ptpcert.transport import make_factory

    res = R.RunResult(tool_version="test", started="")
    factory = make_factory(url, profile)
    try:
        Runner(factory, profile, RunOptions()).run(cases, res)
    finally:
        factory.shutdown()
    return res
