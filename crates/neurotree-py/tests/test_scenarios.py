"""Scenario files run from Python: results that pass and fail as ``neurotree test`` reports
them, with Python leaves, and clear errors for files that do not read."""

from __future__ import annotations

import pathlib
from typing import Any

import neurotree as nt
from conftest import REPO

DOOR = """<root BTCPP_format="4"><BehaviorTree ID="Main">
  <Fallback>
    <OpenDoor/>
    <Sequence>
      <SmashDoor/>
      <Script code="smashed := true"/>
    </Sequence>
  </Fallback>
</BehaviorTree></root>"""


def write(folder: pathlib.Path, name: str, text: str) -> pathlib.Path:
    path = folder / name
    path.write_text(text, encoding="utf-8")
    return path


def door_registry(calls: list[Any]) -> nt.Registry:
    """SmashDoor in Python: it records the robot it was ticked with, and succeeds."""
    reg = nt.Registry()

    @reg.action("SmashDoor")
    def smash(node: nt.Node, robot: Any) -> nt.Status:
        calls.append(robot)
        return nt.SUCCESS

    return reg


def test_a_passing_scenario_runs_python_leaves_with_the_robot(tmp_path: pathlib.Path) -> None:
    write(tmp_path, "door.xml", DOOR)
    scenario = write(
        tmp_path,
        "door.toml",
        """name = "a locked door is smashed"
tree = "door.xml"
[mocks]
OpenDoor = "FAILURE"
[[expect]]
tick = 1
root = "SUCCESS"
nodes = { SmashDoor = "SUCCESS", OpenDoor = "FAILURE" }
blackboard = { smashed = true }
""",
    )
    calls: list[Any] = []
    robot = {"id": 7}
    results = nt.run_scenarios([scenario], registry=door_registry(calls), robot=robot)
    assert results.passed and bool(results), results.report()
    assert len(results) == 1 and results.failed == []
    result = results[0]
    assert result.passed and result.problems == []
    assert (result.name, result.file) == ("a locked door is smashed", str(scenario))
    assert result.report() == "test a locked door is smashed ... ok"
    assert results.report().endswith("\n\n1 passed, 0 failed")
    # One tick, one call of the Python leaf, with the robot given.
    assert calls == [robot]


def test_a_failing_scenario_says_what_did_not_hold(tmp_path: pathlib.Path) -> None:
    write(tmp_path, "door.xml", DOOR)
    good = write(tmp_path, "good.toml", 'tree = "door.xml"\nmocks = { OpenDoor = "SUCCESS" }\n')
    bad = write(
        tmp_path,
        "stuck.toml",
        """tree = "door.xml"
[mocks]
OpenDoor = "FAILURE"
SmashDoor = "FAILURE"
[[expect]]
root = "SUCCESS"
blackboard = { smashed = true }
[[expect]]
tick = 3
root = "RUNNING"
""",
    )
    results = nt.run_scenarios([good, bad], registry=door_registry([]))
    assert not results and not results.passed
    assert [r.passed for r in results] == [True, False]
    assert results.failed == [results[1]]
    stuck = results[1]
    assert stuck.name == "stuck" and not stuck
    assert stuck.problems == [
        "tick 3: not reached; the run ended after tick 1 with FAILURE",
        "end (tick 1): root is FAILURE, expected SUCCESS",
        "end (tick 1): blackboard `smashed` is not set, expected true",
    ]
    assert stuck.report() == (
        "test stuck ... FAILED\n"
        "    tick 3: not reached; the run ended after tick 1 with FAILURE\n"
        "    end (tick 1): root is FAILURE, expected SUCCESS\n"
        "    end (tick 1): blackboard `smashed` is not set, expected true"
    )
    assert results.report().endswith("\n\n1 passed, 1 failed")
    assert repr(results) == "<ScenarioResults: 1 passed, 1 failed>"


def test_a_bad_file_fails_naming_its_file_line_and_column(tmp_path: pathlib.Path) -> None:
    broken = write(tmp_path, "broken.toml", 'tree = "x.xml"\nticks = "many"\n')
    missing = tmp_path / "missing.toml"
    unknown = write(tmp_path, "unknown.toml", 'tree = "door.xml"\nmock = { OpenDoor = "FAILURE" }\n')
    results = nt.run_scenarios([broken, missing, unknown])
    assert [r.name for r in results] == ["broken", "missing", "unknown"]
    assert not any(results)
    (problem,) = results[0].problems
    assert problem.startswith(f"{broken}:2:9: error: "), problem
    assert "neurotree test --help" in problem
    (problem,) = results[1].problems
    assert problem.startswith(f"{missing}: cannot read the scenario: "), problem
    (problem,) = results[2].problems
    assert problem.startswith(f"{unknown}:2:1: error: unknown field `mock`"), problem


def test_a_tree_that_does_not_load_or_a_leaf_that_raises_fails_its_scenario(tmp_path: pathlib.Path) -> None:
    write(tmp_path, "door.xml", DOOR)
    # Without the registry, SmashDoor has no implementation.
    unloaded = write(tmp_path, "unloaded.toml", 'tree = "door.xml"\nmocks = { OpenDoor = "FAILURE" }\n')
    (result,) = nt.run_scenarios(unloaded)
    assert result.problems[0].startswith("the tree did not load:\n"), result.problems
    assert "unknown node type `SmashDoor`" in result.problems[0]
    assert "mock_unknown = true" in result.problems[0]

    reg = nt.Registry()

    @reg.action("SmashDoor")
    def jammed(node: nt.Node, robot: Any) -> nt.Status:
        raise RuntimeError("the door is jammed")

    (result,) = nt.run_scenarios(unloaded, registry=reg)
    (problem,) = result.problems
    assert problem.startswith("tick 1: the tick failed: "), problem
    assert "SmashDoor" in problem and "the door is jammed" in problem
    # The registry's trees are untouched by the scenario: a tree of it ticks as before.
    tree = reg.load_string(DOOR.replace("<OpenDoor/>", "<AlwaysFailure/>"))
    try:
        tree.tick_once()
    except nt.NodeError as e:
        assert isinstance(e.__cause__, RuntimeError)
    else:
        raise AssertionError("the leaf did not raise")


def test_the_repository_scenarios_pass_with_nav2s_node_types() -> None:
    files = sorted((REPO / "scenarios").glob("*.toml"))
    assert len(files) >= 5
    reg = nt.Registry()
    reg.add_nav2()
    results = nt.run_scenarios(files, registry=reg)
    assert results.passed, results.report()
    assert len(results) == len(files)
