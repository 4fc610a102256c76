"""Shared by the tests: the repository's paths, and the Python examples of its docs."""

from __future__ import annotations

import pathlib
import re

import pytest

REPO = pathlib.Path(__file__).resolve().parents[3]


def python_blocks(doc: pathlib.Path) -> list[str]:
    """The ```python code blocks of a Markdown file, in order."""
    return re.findall(r"```python\n(.*?)```", doc.read_text(encoding="utf-8"), re.S)


@pytest.fixture
def repo() -> pathlib.Path:
    return REPO
