"""The README's Python example and the guide's examples run as written."""

from __future__ import annotations

from conftest import REPO, python_blocks


def test_readme_python_example_runs() -> None:
    blocks = python_blocks(REPO / "README.md")
    assert len(blocks) == 1, "the README has one Python example"
    scope: dict[str, object] = {}
    exec(compile(blocks[0], "README.md", "exec"), scope)
    # The example's own assertions ran; it left its tree behind.
    assert "tree" in scope


def test_guide_examples_run_in_order() -> None:
    blocks = python_blocks(REPO / "docs" / "guide" / "python.md")
    assert len(blocks) >= 5
    scope: dict[str, object] = {}
    for i, block in enumerate(blocks):
        exec(compile(block, f"docs/guide/python.md block {i + 1}", "exec"), scope)
