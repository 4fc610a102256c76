"""A tree built in code, watched: status changes, the JSON trace, why it failed, coverage.

Run with `python crates/neurotree-py/examples/watch_failures.py`; `mypy --strict` checks it.
"""

from __future__ import annotations

import json

import neurotree as nt


def grip(node: nt.Node, robot: dict[str, bool]) -> nt.Status:
    if robot["holding"]:
        return nt.SUCCESS
    return node.fail("nothing between the fingers", code=7)


def main() -> None:
    b = nt.Builder()
    with b.node("Fallback", name="pick"):
        with b.node("RetryUntilSuccessful", num_attempts=2):
            b.action("grip", grip)
        b.leaf("AlwaysFailure", name="give_up")
    tree = b.build()

    changes: list[str] = []
    tree.on_status_change(lambda path, previous, status, at: changes.append(f"{path}: {status.name}"))
    trace: list[dict[str, object]] = []
    tree.on_trace_line(lambda line: trace.append(json.loads(line)))
    coverage = tree.start_coverage()

    status = tree.tick_once({"holding": False})
    # The chain from the root to the node that decided it, with the Fallback's tries.
    print(status.name, "because:", tree.last_failure(), sep="\n")
    print(len(changes), "changes,", len(trace), "trace lines")
    status = tree.tick_once({"holding": True})
    print(status.name, f"{coverage.percent:.0f}% covered; never reached: {coverage.never_reached()}")


if __name__ == "__main__":
    main()
