import subprocess
import sys

import satgnc
from satgnc import cli


def test_version_matches_package():
    assert satgnc.__version__ == "0.1.0"


def test_cli_version(capsys):
    assert cli.main(["--version"]) == 0
    assert capsys.readouterr().out.strip() == satgnc.__version__


def test_cli_without_command_prints_help_and_returns_2(capsys):
    assert cli.main([]) == 2
    assert "reproduce" in capsys.readouterr().out


def test_console_script_runs():
    out = subprocess.run([sys.executable, "-m", "satgnc.cli", "--version"], capture_output=True, text=True)
    assert out.returncode == 0 and out.stdout.strip() == "0.1.0"
