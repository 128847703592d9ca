"""``ptpcert capture --wireshark-plugin``: where the dissector is, installing it into
Wireshark's personal Lua plugin folder (which tshark then loads by itself), and bad folders
refused in one line with exit status 2 (docs/wireshark.md, "Install")."""

from __future__ import annotations

import os
import shutil
import subprocess
from pathlib import Path

import pytest

from ptpcert.capture.wireshark_plugin import PLUGIN_NAME, plugin_path
from ptpcert.cli.main import main as cli_main

TSHARK = shutil.which("tshark")


def test_the_command_prints_where_the_dissector_is(capsys):
    assert cli_main(["capture", "--wireshark-plugin"]) == 0
    out = capsys.readouterr().out.strip()
    assert Path(out) == plugin_path() and Path(out).name == PLUGIN_NAME and Path(out).is_file()
    assert Path(out).read_text().startswith("-- ptpcert.lua")


def test_install_copies_it_into_the_personal_plugin_folder(tmp_path, monkeypatch, capsys):
    monkeypatch.setenv("HOME", str(tmp_path))
    assert cli_main(["capture", "--wireshark-plugin", "install"]) == 0
    target = tmp_path / ".local" / "lib" / "wireshark" / "plugins" / PLUGIN_NAME
    assert target.read_bytes() == plugin_path().read_bytes()
    assert "installed" in capsys.readouterr().out
    assert cli_main(["capture", "--wireshark-plugin", "install"]) == 0
    assert "unchanged" in capsys.readouterr().out
    target.write_text("-- an older copy\n")
    assert cli_main(["capture", "--wireshark-plugin", "install"]) == 0
    assert "replacing" in capsys.readouterr().out and target.read_bytes() == plugin_path().read_bytes()
    if TSHARK:   # tshark loads it from there by itself
        p = subprocess.run([TSHARK, "-G", "plugins"], capture_output=True, text=True, timeout=60,
                           env={**os.environ, "HOME": str(tmp_path)})
        assert str(target) in p.stdout


@pytest.mark.parametrize("argv, says", [
    (["--wireshark-plugin", "instal"], "--wireshark-plugin instal"),
    (["--wireshark-plugin", "install", "--plugin-dir", "{file}"], "is not a folder"),
    (["--wireshark-plugin", "install", "--plugin-dir", "{file}/sub"], "cannot install the plugin there"),
    (["--wireshark-plugin", "install", "--plugin-dir", "{tmp}"], "exists and is not a regular file"),
    (["--plugin-dir", "{tmp}"], "--plugin-dir needs --wireshark-plugin install"),
    (["--wireshark-plugin", "--plugin-dir", "{tmp}"], "--plugin-dir needs --wireshark-plugin install"),
])
def test_bad_plugin_paths_are_refused_in_one_line(tmp_path, capsys, argv, says):
    (tmp_path / "a-file").write_text("x")
    (tmp_path / PLUGIN_NAME).mkdir()
    argv = [a.format(file=tmp_path / "a-file", tmp=tmp_path) for a in argv]
    assert cli_main(["capture", *argv]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and says in err, err
