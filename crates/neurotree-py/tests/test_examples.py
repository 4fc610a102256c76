"""The examples (which CI also checks with mypy --strict) run and print what they show."""

from __future__ import annotations

import runpy

import pytest
from conftest import REPO

EXAMPLES = REPO / "crates" / "neurotree-py" / "examples"


def test_patrol(capsys: pytest.CaptureFixture[str]) -> None:
    runpy.run_path(str(EXAMPLES / "patrol.py"), run_name="__main__")
    assert capsys.readouterr().out == "SUCCESS ['drive to 3'] 3 None\n"


def test_watch_failures(capsys: pytest.CaptureFixture[str]) -> None:
    runpy.run_path(str(EXAMPLES / "watch_failures.py"), run_name="__main__")
    out = capsys.readouterr().out
    assert "tried pick/RetryUntilSuccessful: nothing between the fingers (error 7)" in out
    assert out.endswith("SUCCESS 82% covered; never reached: []\n")
