"""The side-by-side script of crates/neurotree-bench/compare runs, in a few ticks, and
checks that each library's tree returns SUCCESS on every tick it times."""

from __future__ import annotations

import json
import subprocess
import sys

from conftest import REPO

SCRIPT = REPO / "crates" / "neurotree-bench" / "compare" / "python_tree1111.py"


def test_the_comparison_script_runs() -> None:
    done = subprocess.run(
        [sys.executable, str(SCRIPT), "--ticks", "20", "--pytrees-ticks", "2"],
        capture_output=True,
        text=True,
        timeout=300,
        check=True,
    )
    lines = [json.loads(line) for line in done.stdout.splitlines() if line.startswith("{")]
    names = [line["name"] for line in lines]
    assert names[0] == "neurotree, python leaves"
    assert "neurotree, built-ins, ticked by rust (tick_times)" in names
    assert all(line.get("ns_per_node", 1) > 0 for line in lines)
    assert "vs neurotree" in done.stdout
