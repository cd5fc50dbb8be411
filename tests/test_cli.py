"""`tvmedit --help` lists every subcommand, and each subcommand's --help runs."""

import subprocess
import sys

import pytest

from tvmedit.cli import COMMANDS


def _run(*args):
    return subprocess.run([sys.executable, "-m", "tvmedit", *args], capture_output=True, text=True)


def test_top_level_help_lists_every_command():
    result = _run("--help")
    assert result.returncode == 0
    for name in COMMANDS:
        assert name in result.stdout


@pytest.mark.parametrize("name", COMMANDS)
def test_each_subcommand_help_runs(name):
    result = _run(name, "--help")
    assert result.returncode == 0, result.stderr
    assert result.stdout.startswith(f"usage: tvmedit {name}")


def test_unknown_command_is_refused():
    result = _run("frobnicate")
    assert result.returncode == 2 and "invalid choice" in result.stderr
