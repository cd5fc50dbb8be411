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


def test_a_reader_that_goes_away_ends_the_command_quietly(small_library):
    # `tvmedit path ... | head -1`: the command ends as a shell tool does, exit 141, no noise.
    from interrupt import ROOT

    child = subprocess.Popen([sys.executable, "-m", "tvmedit", "path", str(small_library), "0", "3", "--loops",
                              "3000"], cwd=ROOT, stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    child.stdout.readline()
    child.stdout.close()
    err = child.stderr.read().decode()
    assert child.wait(timeout=60) == 141 and err == "", err
