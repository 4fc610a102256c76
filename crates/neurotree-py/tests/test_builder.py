"""nt.Builder: the same trees as from XML, built in code, with exact statuses and counts."""

from __future__ import annotations

from typing import Any

import neurotree as nt
import pytest


def test_a_built_tree_ticks_as_its_xml_would() -> None:
    said: list[str] = []

    def say(node: nt.Node, robot: Any) -> nt.Status:
        said.append(node.input("message"))
        return nt.SUCCESS

    class Move(nt.StatefulAction):
        ports = {"goal": str, "steps": nt.Output(int)}

        def on_start(self, node: nt.Node, robot: Any) -> nt.Status:
            return nt.RUNNING

        def on_running(self, node: nt.Node, robot: Any) -> nt.Status:
            node.output("steps", 3)
            return nt.SUCCESS

    b = nt.Builder()
    with b.node("Sequence", name="patrol"):
        b.condition("battery_ok", lambda node, robot: robot["battery"] >= node.input("min"), ports={"min": int}, min=20)
        with b.node("Repeat", num_cycles=2):
            b.action("say", say, ports={"message": str}, message="{word}")
        b.stateful_action("move", Move, goal="dock", steps="{steps}")
        b.leaf("AlwaysSuccess")
    tree = b.build(clock=nt.ManualClock())
    tree.blackboard["word"] = "lap"
    robot = {"battery": 80}
    assert tree.tick_once(robot) is nt.RUNNING
    assert said == ["lap", "lap"]
    assert tree.tick_once(robot) is nt.SUCCESS
    assert tree.blackboard["steps"] == 3
    assert tree.paths()[:3] == ["patrol", "patrol/battery_ok", "patrol/Repeat"]
    robot["battery"] = 5
    assert tree.tick_once(robot) is nt.FAILURE
    assert said == ["lap", "lap"]


def test_async_leaves_and_sleep_in_a_built_tree() -> None:
    async def twice(node: nt.Node, robot: Any) -> nt.Status:
        await nt.next_tick()
        return nt.SUCCESS

    clock = nt.ManualClock()
    b = nt.Builder()
    with b.node("Sequence"):
        b.action("twice", twice)
        b.leaf("Sleep", msec=100)
    tree = b.build(clock=clock)
    assert tree.tick_once() is nt.RUNNING
    assert tree.tick_once() is nt.RUNNING  # twice done, Sleep started
    clock.advance(0.1)
    assert tree.tick_once() is nt.SUCCESS


def test_builder_errors_are_clear() -> None:
    b = nt.Builder()
    with pytest.raises(ValueError, match="no built-in node"):
        b.open("Sequense")
    with pytest.raises(ValueError, match="num_cycles"):
        b.open("Repeat", num_cycles="often")
    with pytest.raises(ValueError, match="registry"):
        b.leaf("Script", code="x := 1")
    unclosed = nt.Builder()
    unclosed.open("Sequence")
    with pytest.raises(ValueError):
        unclosed.build()
    done = nt.Builder()
    done.leaf("AlwaysSuccess")
    done.build()
    with pytest.raises(RuntimeError, match="built its tree"):
        done.build()
