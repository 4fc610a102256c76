"""Observers, last_failure, coverage, saved state, reload, mocks, substitution, Nav2, async."""

from __future__ import annotations

import json
from typing import Any

import neurotree as nt
import pytest

FALLBACK = """
<root BTCPP_format="4"><BehaviorTree ID="Main">
  <Fallback name="either">
    <Blocked name="path"/>
    <Inverter><AlwaysSuccess/></Inverter>
  </Fallback>
</BehaviorTree></root>
"""


def blocked_registry() -> nt.Registry:
    reg = nt.Registry()

    @reg.action("Blocked")
    def blocked(node: nt.Node, robot: Any) -> nt.Status:
        return node.fail("obstacle ahead", code=106)

    return reg


def test_status_changes_go_to_a_callable() -> None:
    tree = blocked_registry().load_string(FALLBACK)
    changes: list[tuple[str, nt.Status, nt.Status, float]] = []
    tree.on_status_change(lambda path, previous, status, at: changes.append((path, previous, status, at)))
    assert tree.tick_once() is nt.FAILURE
    assert changes[0] == ("either", nt.Status.IDLE, nt.Status.RUNNING, 0.0)
    assert ("either/path", nt.Status.IDLE, nt.Status.FAILURE, 0.0) in changes
    assert changes[-1][1:3] == (nt.Status.FAILURE, nt.Status.IDLE)
    assert all(isinstance(c[2], nt.Status) for c in changes)


def test_trace_lines_are_the_json_lines_of_run_jsonl() -> None:
    tree = blocked_registry().load_string(FALLBACK)
    lines: list[str] = []
    tree.on_trace_line(lines.append)
    tree.tick_once()
    records = [json.loads(line) for line in lines]
    assert records, "a tick writes trace lines"
    assert all("\n" not in line for line in lines)
    assert any(r.get("node") == "either/path" for r in records)


def test_last_failure_names_the_leaf_and_its_reason() -> None:
    tree = blocked_registry().load_string(FALLBACK)
    assert tree.last_failure() is None
    assert tree.tick_once() is nt.FAILURE
    failure = tree.last_failure()
    assert failure is not None
    assert failure.chain[0][0] == "either"
    assert "obstacle ahead" in str(failure)


def test_coverage_reports_outcomes_seen() -> None:
    reg = nt.Registry()
    reg.condition("Flip")(lambda node, robot: robot["ok"])
    tree = reg.load_string(
        '<root BTCPP_format="4"><BehaviorTree ID="M"><Fallback><Flip/><AlwaysFailure/></Fallback></BehaviorTree></root>'
    )
    coverage = tree.start_coverage()
    tree.tick_once({"ok": True})
    first = coverage.percent
    assert "Fallback/AlwaysFailure" in coverage.never_reached()
    tree.tick_once({"ok": False})
    assert coverage.percent > first
    assert coverage.never_reached() == []
    assert "Fallback/Flip" in coverage.report()


MOVE = """
<root BTCPP_format="4"><BehaviorTree ID="Main">
  <Sequence>
    <Script code="x := 1"/>
    <Sleep msec="1000"/>
    <Script code="x := 2"/>
  </Sequence>
</BehaviorTree></root>
"""


def test_saved_state_restores_into_another_tree() -> None:
    clock = nt.ManualClock()
    reg = nt.Registry()
    tree = reg.load_string(MOVE, clock=clock)
    assert tree.tick_once() is nt.RUNNING
    saved = tree.save_state()
    assert isinstance(saved, bytes)
    elsewhere = nt.ManualClock()
    other = reg.load_string(MOVE, clock=elsewhere)
    other.restore_state(saved)
    assert other.blackboard["x"] == 1
    elsewhere.advance(1.0)
    assert other.tick_once() is nt.SUCCESS
    assert other.blackboard["x"] == 2
    with pytest.raises(ValueError):
        other.restore_state(b"not a state")


def test_reload_keeps_unchanged_nodes_and_halts_changed_running_ones() -> None:
    reg = nt.Registry()
    halts = [0]

    class Wait(nt.StatefulAction):
        def on_start(self, node: nt.Node, robot: Any) -> nt.Status:
            return nt.RUNNING

        def on_running(self, node: nt.Node, robot: Any) -> nt.Status:
            return nt.RUNNING

        def on_halted(self, node: nt.Node, robot: Any) -> None:
            halts[0] += 1

    reg.stateful_action("Wait", Wait)
    v1 = '<root BTCPP_format="4"><BehaviorTree ID="M"><SequenceWithMemory><AlwaysSuccess/><Wait name="w"/></SequenceWithMemory></BehaviorTree></root>'
    v2 = v1.replace('<Wait name="w"/>', "<AlwaysSuccess/>")
    tree = reg.load_string(v1)
    assert tree.tick_once() is nt.RUNNING
    kept, restarted, halted = tree.reload(v2)
    assert (kept, halted) == (2, 1)
    assert halts[0] == 1
    assert tree.tick_once() is nt.SUCCESS


def test_mocks_replace_leaves_by_name() -> None:
    reg = nt.Registry()
    reg.action("Drive")(lambda node, robot: nt.FAILURE)
    reg.mock("Drive", "RUNNING*2,SUCCESS")
    tree = reg.load_string('<root BTCPP_format="4"><BehaviorTree ID="M"><Drive/></BehaviorTree></root>')
    assert [tree.tick_once() for _ in range(3)] == [nt.RUNNING, nt.RUNNING, nt.SUCCESS]
    with pytest.raises(ValueError):
        reg.mock("Drive", "sometimes")


def test_substitution_rules_replace_nodes() -> None:
    reg = nt.Registry()
    reg.substitute(
        json.dumps(
            {
                "TestNodeConfigs": {"Done": {"return_status": "SUCCESS", "post_script": "n := 7"}},
                "SubstitutionRules": {"Drive*": "Done"},
            }
        )
    )
    tree = reg.load_string('<root BTCPP_format="4"><BehaviorTree ID="M"><DriveToDock/></BehaviorTree></root>')
    assert tree.tick_once() is nt.SUCCESS
    assert tree.blackboard["n"] == 7


def test_nav2_node_types_load_a_navigator_with_python_leaves() -> None:
    reg = nt.Registry()
    planned = [0]

    @reg.action("ComputePathToPose", ports={"goal": object, "path": nt.Output(object), "planner_id": str})
    def plan(node: nt.Node, robot: Any) -> nt.Status:
        planned[0] += 1
        return nt.SUCCESS

    reg.add_nav2()
    assert "PipelineSequence" in reg.node_types()
    tree = reg.load_string(
        '<root BTCPP_format="4"><BehaviorTree ID="M"><RecoveryNode number_of_retries="1">'
        '<ComputePathToPose goal="{goal}" path="{path}" planner_id="GridBased"/><AlwaysSuccess/>'
        "</RecoveryNode></BehaviorTree></root>"
    )
    assert tree.tick_once() is nt.SUCCESS
    assert planned[0] == 1
    with pytest.raises(ValueError):
        reg.add_nav2("rolling")


def test_async_def_leaves_run_over_ticks_and_close_on_halt() -> None:
    reg = nt.Registry()
    log: list[str] = []

    @reg.action("Count", ports={"n": int})
    async def count(node: nt.Node, robot: Any) -> nt.Status:
        for i in range(node.input("n")):
            log.append(f"step {i}")
            await nt.next_tick()
        return nt.SUCCESS

    @reg.action("Nap")
    async def nap(node: nt.Node, robot: Any) -> nt.Status:
        try:
            await nt.sleep(node, 1.0)
            return nt.SUCCESS
        finally:
            log.append("nap closed")

    clock = nt.ManualClock()
    tree = reg.load_string(
        '<root BTCPP_format="4"><BehaviorTree ID="M"><Sequence><Count n="3"/><Nap/></Sequence></BehaviorTree></root>',
        clock=clock,
    )
    assert [tree.tick_once() for _ in range(3)] == [nt.RUNNING] * 3
    assert log == ["step 0", "step 1", "step 2"]
    assert tree.tick_once() is nt.RUNNING  # Count done, Nap started
    clock.advance(0.5)
    assert tree.tick_once() is nt.RUNNING
    tree.halt()
    assert log[-1] == "nap closed"
    # Afresh: Count runs again from its start.
    assert tree.tick_once() is nt.RUNNING
    assert log[-1] == "step 0"


def test_a_stateful_actions_attributes_are_saved_and_restored() -> None:
    reg = nt.Registry()

    class Count(nt.StatefulAction):
        def __init__(self) -> None:
            self.seen = 0

        def on_start(self, node: nt.Node, robot: Any) -> nt.Status:
            self.seen = 1
            return nt.RUNNING

        def on_running(self, node: nt.Node, robot: Any) -> nt.Status:
            self.seen += 1
            node.set("seen", self.seen)
            return nt.SUCCESS if self.seen == 4 else nt.RUNNING

    reg.stateful_action("Count", Count)
    xml = '<root BTCPP_format="4"><BehaviorTree ID="M"><Count/></BehaviorTree></root>'
    tree = reg.load_string(xml)
    assert [tree.tick_once() for _ in range(2)] == [nt.RUNNING, nt.RUNNING]
    saved = tree.save_state()
    resumed = reg.load_string(xml)
    resumed.restore_state(saved)
    assert resumed.tick_once() is nt.RUNNING
    assert resumed.blackboard["seen"] == 3
    assert resumed.tick_once() is nt.SUCCESS


def test_lists_and_dicts_on_the_blackboard_are_saved() -> None:
    xml = '<root BTCPP_format="4"><BehaviorTree ID="M"><AlwaysSuccess/></BehaviorTree></root>'
    reg = nt.Registry()
    tree = reg.load_string(xml)
    tree.blackboard["pose"] = {"x": 1.0, "tags": ["a", None]}
    tree.blackboard["n"] = 3
    again = reg.load_string(xml)
    again.restore_state(tree.save_state())
    assert again.blackboard.to_dict() == {"pose": {"x": 1.0, "tags": ["a", None]}, "n": 3}


TWO_WAYS = """
<root BTCPP_format="4"><BehaviorTree ID="M">
  <Fallback>
    <Sequence><Low/><AlwaysSuccess/></Sequence>
    <Sequence><Charged/><AlwaysSuccess/></Sequence>
  </Fallback>
</BehaviorTree></root>"""


def test_last_failure_reaches_each_leaf_that_decided_it_without_reasons() -> None:
    reg = nt.Registry()
    reg.condition("Low")(lambda node, robot: False)
    reg.condition("Charged")(lambda node, robot: False)
    tree = reg.load_string(TWO_WAYS)
    assert tree.tick_once() is nt.FAILURE
    failure = tree.last_failure()
    assert failure is not None
    assert failure.path == "Fallback/Sequence/Charged"
    assert failure.chain == [
        ("Fallback", None),
        ("Fallback/Sequence", None),
        ("Fallback/Sequence/Charged", None),
    ]
    # Both Sequences share a path: `nodes` holds each node once, both leaves among them.
    paths = [path for path, _ in failure.nodes]
    assert "Fallback/Sequence/Low" in paths and "Fallback/Sequence/Charged" in paths
    assert str(failure).splitlines() == [
        "Fallback",
        "  tried Fallback/Sequence: no reason given",
        "    Fallback/Sequence/Low",
        "  tried Fallback/Sequence: no reason given",
        "  Fallback/Sequence",
        "    Fallback/Sequence/Charged",
    ]


def test_statuses_print_as_their_names() -> None:
    assert str(nt.SUCCESS) == "SUCCESS" and repr(nt.SUCCESS) == "SUCCESS"
    assert f"{nt.FAILURE}" == "FAILURE"
    assert [str(s) for s in nt.Status] == ["IDLE", "RUNNING", "SUCCESS", "FAILURE", "SKIPPED"]
    # Still the numbers BehaviorTree.CPP uses.
    assert nt.SUCCESS == 2
