"""The documentation site (mkdocs.yml, docs/): it builds in strict mode (a broken link, a bad
anchor or a page left out of the navigation fails), and its generated reference pages list
every profile key of every procedure and every case of every bundled profile, so that a key
or a case added to the code cannot be missing from the site. The README's two commands stay
the ones CI runs."""

from __future__ import annotations

import html
import importlib.util
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


def _have_mkdocs() -> bool:
    return all(importlib.util.find_spec(m) is not None for m in ("mkdocs", "material"))


@pytest.fixture(scope="module")
def site(tmp_path_factory) -> Path:
    if not _have_mkdocs():
        pytest.skip("mkdocs and mkdocs-material are not installed (pip install -e '.[docs]'; .ci/run installs them)")
    out = tmp_path_factory.mktemp("site")
    env = {**os.environ, "NO_MKDOCS_2_WARNING": "1"}
    p = subprocess.run([sys.executable, "-m", "mkdocs", "build", "--strict", "--config-file", str(ROOT / "mkdocs.yml"),
                        "--site-dir", str(out)], cwd=ROOT, capture_output=True, text=True, timeout=300, env=env)
    assert p.returncode == 0, f"mkdocs build --strict failed:\n{p.stdout}\n{p.stderr}"
    return out


def _page(site: Path, uri: str) -> str:
    """The text of a built page (its HTML, tags removed, entities decoded)."""
    raw = (site / uri / "index.html").read_text("utf-8")
    return html.unescape(re.sub(r"<[^>]+>", "", raw))


def test_every_profile_key_of_every_procedure_is_in_the_site(site):
    from ptpcert.registry import procedures
    from ptpcert.schema import COMMON

    text = _page(site, "reference/profile-keys")
    keys = [k.path for k in COMMON] + [k.path for p in procedures() for k in p.profile_schema()]
    missing = [k for k in keys if k not in text]
    assert not missing, f"profile keys missing from reference/profile-keys: {missing}"
    for p in procedures():
        assert p.title in text


def test_every_setup_is_described_and_listed(site):
    from ptpcert.registry import procedures

    guide = (ROOT / "docs" / "iut-interfaces.md").read_text("utf-8")
    keys = _page(site, "reference/profile-keys")
    for p in procedures():
        for name in p.setups:
            assert f"| `{name}` |" in guide, f"the setup {name} of {p.title} is not described in docs/iut-interfaces.md"
            assert name in keys


def test_every_case_of_every_bundled_profile_is_in_the_site(site):
    from ptpcert.cli.profile import examples
    from ptpcert.paths import bundled_profiles
    from ptpcert.profile import load_profile
    from ptpcert.scenario import load_vector_sets
    from ptpcert.suite import load_suite

    vectors = load_vector_sets()
    assert examples(), "no bundled profile"
    for name in examples():
        profile = load_profile(Path(str(bundled_profiles().joinpath(f"{name}.toml"))))
        cases = load_suite(profile, vectors)
        text = _page(site, f"reference/cases-{name}")
        ids = set(re.findall(r"[A-Z0-9][A-Z0-9.\-_]+", text))
        missing = [v.id for v in cases if v.id not in ids]
        assert cases and not missing, f"cases of {name} missing from its page: {missing[:10]}"


def test_the_status_events_rules_and_commands_are_in_the_site(site):
    from ptpcert.cli import build_parser
    from ptpcert.rules import catalogues
    from ptpcert.status import catalogue

    status = _page(site, "reference/status")
    assert all(e.notation in status for e in catalogue().values())
    assert "Table 8-3" in status and "16#090C" in status
    rules = _page(site, "reference/rules")
    assert all(r.id in rules for c in catalogues() for r in c)
    cli = _page(site, "reference/cli")
    sub = next(a for a in build_parser()._actions if a.__class__.__name__ == "_SubParsersAction")
    assert all(f"ptpcert {name}" in cli for name in sub.choices)


def test_the_guides_show_the_bundled_profiles_as_shipped(site):
    text = _page(site, "procedure-rk-512")
    shipped = (ROOT / "conformance/profiles/rk512-reference.toml").read_text("utf-8")
    rt = re.search(r"^response_time_ms = \d+", shipped, re.M).group(0)
    assert rt in text


def _readme_commands() -> list[str]:
    readme = (ROOT / "README.md").read_text("utf-8")
    block = readme.split("```sh\n", 1)[1].split("```", 1)[0]
    return [line for line in block.splitlines() if line and not line.startswith("#")]


def test_the_readme_keeps_its_two_commands_and_ci_runs_the_second():
    install_and_run, tests = _readme_commands()[:2]
    assert install_and_run.startswith("python3 -m pip install . && ptpcert run --iut ")
    assert tests.startswith("python3 -m pip install -e '.[test")
    ci = (ROOT / ".ci" / "run").read_text("utf-8")
    # CI runs the README's test command: the same install (quiet) with the docs extra beside
    # the test one (so that this module builds the site there), then its pytest runs exactly
    install, runs = tests.split(" && ", 1)
    assert "'.[test,docs]'" in install
    ci_line = next(line for line in ci.splitlines() if line.endswith(runs))
    assert ci_line == install.replace(" install -e ", " install -q -e ") + " && " + runs
    started = (ROOT / "docs" / "getting-started.md").read_text("utf-8")
    assert install_and_run in started and tests in started


def test_the_readme_profile_is_a_valid_profile(tmp_path):
    from ptpcert.profile import load_profile

    readme = (ROOT / "README.md").read_text("utf-8")
    profile = tmp_path / "readme.toml"
    profile.write_text(readme.split("```toml\n", 1)[1].split("```", 1)[0], "utf-8")
    assert load_profile(profile).procedure.title == "3964/3964R"


def test_the_readme_links_into_the_site_resolve():
    readme = (ROOT / "README.md").read_text("utf-8")
    links = re.findall(r"\]\((docs/[^)#]+)", readme)
    assert links and all((ROOT / link).is_file() for link in links), links
