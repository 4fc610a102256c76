"""The API of issue 32's block, exactly as written there, with exact statuses and counts."""

from __future__ import annotations

from typing import Any

import neurotree as nt
import pytest

XML = """
<root BTCPP_format="4" main_tree_to_execute="Main">
  <BehaviorTree ID="Main">
    <Sequence>
      <Script code="laps := 0"/>
      <BatteryOK min="20"/>
      <Repeat num_cycles="2">
        <Sequence>
          <Say message="lap"/>
          <Script code="laps += 1"/>
        </Sequence>
      </Repeat>
      <MoveTo goal="dock" steps="{steps}"/>
    </Sequence>
  </BehaviorTree>
</root>
"""


def make_registry(calls: list[str]) -> nt.Registry:
    reg = nt.Registry()

    @reg.condition("BatteryOK", ports={"min": int})
    def battery_ok(node: nt.Node, robot: Any) -> bool:
        calls.append("BatteryOK")
        return bool(robot["battery"] >= node.input("min"))

    @reg.action("Say", ports={"message": str})
    def say(node: nt.Node, robot: Any) -> nt.Status:
        robot["said"].append(node.input("message"))
        return nt.SUCCESS

    class MoveTo(nt.StatefulAction):
        ports = {"goal": str, "steps": nt.Output(int)}

        def on_start(self, node: nt.Node, robot: Any) -> nt.Status:
            calls.append("start " + node.input("goal"))
            return nt.RUNNING

        def on_running(self, node: nt.Node, robot: Any) -> nt.Status:
            calls.append("running")
            node.output("steps", 3)
            return nt.SUCCESS

        def on_halted(self, node: nt.Node, robot: Any) -> None:
            calls.append("halted")

    reg.stateful_action("MoveTo", MoveTo)
    return reg


def test_the_issue_block_runs_as_written() -> None:
    calls: list[str] = []
    reg = make_registry(calls)
    clock = nt.ManualClock()
    tree = reg.load_string(XML, clock=clock)
    robot = {"battery": 80, "said": []}
    status = tree.tick_once(robot)
    assert status is nt.RUNNING
    assert isinstance(status, nt.Status)
    assert robot["said"] == ["lap", "lap"]
    assert calls == ["BatteryOK", "start dock"]
    assert tree.tick_while_running(robot, max_ticks=100) is nt.SUCCESS
    assert calls == ["BatteryOK", "start dock", "running"]
    clock.advance(0.1)
    assert clock.now == pytest.approx(0.1)
    laps = tree.blackboard["laps"]
    assert laps == 2 and type(laps) is int
    assert tree.blackboard["steps"] == 3
    tree.blackboard["target"] = {"x": 1.0}
    assert tree.blackboard["target"] == {"x": 1.0}


def test_a_condition_that_fails_stops_the_sequence() -> None:
    calls: list[str] = []
    tree = make_registry(calls).load_string(XML)
    robot = {"battery": 10, "said": []}
    assert tree.tick_once(robot) is nt.FAILURE
    assert robot["said"] == []
    assert calls == ["BatteryOK"]


def test_status_members_are_those_of_btcpp() -> None:
    assert [int(s) for s in nt.Status] == [0, 1, 2, 3, 4]
    assert nt.SUCCESS is nt.Status.SUCCESS and nt.FAILURE is nt.Status.FAILURE
    assert nt.RUNNING is nt.Status.RUNNING


def test_load_file_reads_a_file_and_its_includes(tmp_path: Any) -> None:
    (tmp_path / "sub.xml").write_text(
        '<root BTCPP_format="4"><BehaviorTree ID="Count"><Script code="n += 1"/></BehaviorTree></root>'
    )
    (tmp_path / "main.xml").write_text(
        '<root BTCPP_format="4" main_tree_to_execute="Main"><include path="sub.xml"/>'
        '<BehaviorTree ID="Main"><Sequence><Script code="n := 0"/>'
        '<Repeat num_cycles="3"><SubTree ID="Count" _autoremap="true"/></Repeat></Sequence>'
        "</BehaviorTree></root>"
    )
    tree = nt.Registry().load_file(tmp_path / "main.xml", clock=nt.ManualClock())
    assert tree.tick_once() is nt.SUCCESS
    assert tree.blackboard["n"] == 3


def test_blackboard_values_go_both_ways() -> None:
    tree = nt.Registry().load_string(
        '<root BTCPP_format="4"><BehaviorTree ID="Main">'
        '<Script code="i := 7; f := 2.5; s := \'text\'; b := true"/></BehaviorTree></root>'
    )
    assert tree.tick_once() is nt.SUCCESS
    bb = tree.blackboard
    assert (bb["i"], bb["f"], bb["s"], bb["b"]) == (7, 2.5, "text", True)
    assert type(bb["i"]) is int and type(bb["f"]) is float and type(bb["b"]) is bool
    values = {"none": None, "list": [1, "two", [3.0]], "dict": {"a": {"b": [True, None]}}, "big": -(2**63)}
    for key, value in values.items():
        bb[key] = value
    for key, value in values.items():
        assert bb[key] == value
    bb["f"] = 4  # a script's entry takes the type written, as in BehaviorTree.CPP
    assert bb["f"] == 4 and type(bb["f"]) is int
    assert "i" in bb and "nothing" not in bb
    with pytest.raises(KeyError):
        bb["nothing"]
    with pytest.raises(OverflowError):
        bb["huge"] = 2**64
    with pytest.raises(TypeError):
        bb["object"] = object()
    del bb["none"]
    assert "none" not in bb
    assert bb.get("none", 5) == 5
    assert set(bb.to_dict()) == set(bb.keys())


def test_an_entry_of_a_declared_type_keeps_it() -> None:
    reg = nt.Registry()
    reg.action("Set", ports={"speed": nt.Output(float)})(lambda node, robot: node.output("speed", 1.5) or nt.SUCCESS)
    tree = reg.load_string('<root BTCPP_format="4"><BehaviorTree ID="M"><Set speed="{speed}"/></BehaviorTree></root>')
    assert tree.tick_once() is nt.SUCCESS
    tree.blackboard["speed"] = 2
    assert tree.blackboard["speed"] == 2.0 and type(tree.blackboard["speed"]) is float
    with pytest.raises(TypeError, match="speed"):
        tree.blackboard["speed"] = "fast"
    assert tree.blackboard["speed"] == 2.0


def test_registered_rust_types_are_dicts_both_ways() -> None:
    reg = nt.Registry()
    reg.add_nav2()
    tree = reg.load_string(
        '<root BTCPP_format="4"><BehaviorTree ID="M">'
        '<GoalUpdater input_goal="1;2;0.5" output_goal="{goal}"><AlwaysSuccess/></GoalUpdater>'
        "</BehaviorTree></root>"
    )
    assert tree.tick_once() is nt.SUCCESS
    assert tree.blackboard["goal"] == {"x": 1.0, "y": 2.0, "theta": 0.5}
    tree.blackboard["goal"] = {"x": 3.0, "y": -1.0, "theta": 0.0}
    assert tree.blackboard["goal"] == {"x": 3.0, "y": -1.0, "theta": 0.0}
    with pytest.raises(TypeError, match="Pose2D"):
        tree.blackboard["goal"] = {"x": "east"}
    saved = tree.save_state()
    again = reg.load_string(
        '<root BTCPP_format="4"><BehaviorTree ID="M">'
        '<GoalUpdater input_goal="1;2;0.5" output_goal="{goal}"><AlwaysSuccess/></GoalUpdater>'
        "</BehaviorTree></root>"
    )
    again.restore_state(saved)
    assert again.blackboard["goal"] == {"x": 3.0, "y": -1.0, "theta": 0.0}
