"""Load errors, exceptions in leaves, bad returns, bad port values, Ctrl-C."""

from __future__ import annotations

import _thread
import signal
import threading
from typing import Any

import neurotree as nt
import pytest


def test_a_load_error_has_kind_file_line_column_and_check_message() -> None:
    xml = '<root BTCPP_format="4">\n  <BehaviorTree ID="Main">\n    <Nope/>\n  </BehaviorTree>\n</root>\n'
    with pytest.raises(nt.LoadError) as info:
        nt.Registry().load_string(xml)
    error = info.value
    assert error.kind == "UnknownNode"
    assert (error.file, error.line, error.column) == ("<string>", 3, 5)
    assert str(error) == (
        "<string>:3:5: error: unknown node type `Nope`; register it in the Registry before loading"
    )
    assert isinstance(error, nt.NeuroTreeError)


def test_a_load_error_lists_every_error_of_the_tree_in_document_order() -> None:
    xml = (
        '<root BTCPP_format="4">\n  <BehaviorTree ID="Main">\n    <Sequence>\n'
        "      <Nope/>\n"
        '      <Repeat num_cycles="many"><AlwaysSuccess/></Repeat>\n'
        '      <AlwaysSuccess colour="red"/>\n'
        "    </Sequence>\n  </BehaviorTree>\n</root>\n"
    )
    with pytest.raises(nt.LoadError) as info:
        nt.Registry().load_string(xml)
    error = info.value
    assert (error.kind, error.line, error.column) == ("UnknownNode", 4, 7)
    found = [(e.kind, e.line, e.column) for e in error.errors]
    assert found == [("UnknownNode", 4, 7), ("BadValue", 5, 7), ("UnknownPort", 6, 7)]
    assert all(isinstance(e, nt.LoadError) for e in error.errors)
    assert str(error.errors[0]) == str(error)


def test_a_single_load_error_lists_itself() -> None:
    with pytest.raises(nt.LoadError) as info:
        nt.Registry().load_string('<root BTCPP_format="4"><BehaviorTree ID="M"><Nope/></BehaviorTree></root>')
    assert info.value.errors == [info.value]


def test_a_load_error_in_a_file_names_the_file(tmp_path: Any) -> None:
    path = tmp_path / "bad.xml"
    path.write_text('<root BTCPP_format="4"><BehaviorTree ID="Main"><Sequence>\n</root>')
    with pytest.raises(nt.LoadError) as info:
        nt.Registry().load_file(path)
    assert info.value.kind == "Syntax"
    assert info.value.file == str(path)
    assert info.value.line == 2
    with pytest.raises(nt.LoadError) as missing:
        nt.Registry().load_file(tmp_path / "absent.xml")
    assert missing.value.kind == "Io"


def test_a_bad_literal_is_a_load_error_naming_the_port() -> None:
    reg = nt.Registry()
    reg.condition("Check", ports={"min": int})(lambda node, robot: True)
    with pytest.raises(nt.LoadError) as info:
        reg.load_string('<root BTCPP_format="4"><BehaviorTree ID="M"><Check min="lots"/></BehaviorTree></root>')
    assert info.value.kind == "BadValue"
    assert "min" in str(info.value)


XML = """
<root BTCPP_format="4"><BehaviorTree ID="Main">
  <Sequence name="seq">
    <Work name="work"/>
    <Boom name="boom"/>
    <After name="after"/>
  </Sequence>
</BehaviorTree></root>
"""


class Counts:
    def __init__(self) -> None:
        self.starts = 0
        self.halts = 0
        self.after = 0
        self.boom = True


def registry() -> nt.Registry:
    reg = nt.Registry()

    class Work(nt.StatefulAction):
        def on_start(self, node: nt.Node, robot: Counts) -> nt.Status:
            robot.starts += 1
            return nt.SUCCESS

        def on_halted(self, node: nt.Node, robot: Counts) -> None:
            robot.halts += 1

    reg.stateful_action("Work", Work)

    @reg.action("Boom")
    def boom(node: nt.Node, robot: Counts) -> nt.Status:
        if robot.boom:
            raise ValueError("no fuel")
        return nt.SUCCESS

    @reg.action("After")
    def after(node: nt.Node, robot: Counts) -> nt.Status:
        robot.after += 1
        return nt.SUCCESS

    return reg


def test_an_exception_in_a_leaf_is_a_node_error_with_its_cause() -> None:
    tree = registry().load_string(XML)
    robot = Counts()
    with pytest.raises(nt.NodeError) as info:
        tree.tick_once(robot)
    error = info.value
    assert error.path == "seq/boom"
    assert "seq/boom" in str(error) and "ValueError: no fuel" in str(error)
    assert isinstance(error.__cause__, ValueError)
    assert str(error.__cause__) == "no fuel"
    # The tick ended at the exception: the next leaf never ran.
    assert robot.after == 0
    assert [s for _, s in tree.statuses()] == [nt.Status.IDLE] * 4
    # The tree is ready for the next tick, which runs from the start.
    robot.boom = False
    assert tree.tick_once(robot) is nt.SUCCESS
    assert (robot.starts, robot.after) == (2, 1)


def test_a_running_action_is_halted_exactly_once_when_a_leaf_raises() -> None:
    reg = nt.Registry()
    robot = {"halts": 0, "raise": False}

    class Long(nt.StatefulAction):
        def on_start(self, node: nt.Node, robot: Any) -> nt.Status:
            return nt.RUNNING

        def on_running(self, node: nt.Node, robot: Any) -> nt.Status:
            return nt.RUNNING

        def on_halted(self, node: nt.Node, robot: Any) -> None:
            robot["halts"] += 1

    reg.stateful_action("Long", Long)

    @reg.condition("Check")
    def check(node: nt.Node, robot: Any) -> bool:
        if robot["raise"]:
            raise RuntimeError("sensor lost")
        return True

    tree = reg.load_string(
        '<root BTCPP_format="4"><BehaviorTree ID="M"><ReactiveSequence>'
        "<Check/><Long/></ReactiveSequence></BehaviorTree></root>"
    )
    assert tree.tick_once(robot) is nt.RUNNING
    assert tree.tick_once(robot) is nt.RUNNING
    robot["raise"] = True
    with pytest.raises(nt.NodeError) as info:
        tree.tick_once(robot)
    assert isinstance(info.value.__cause__, RuntimeError)
    assert robot["halts"] == 1
    robot["raise"] = False
    assert tree.tick_once(robot) is nt.RUNNING
    assert robot["halts"] == 1


@pytest.mark.parametrize("returned", [None, 2, "SUCCESS", True])
def test_an_action_returning_no_status_is_a_node_error(returned: Any) -> None:
    reg = nt.Registry()
    reg.action("Odd")(lambda node, robot: returned)
    tree = reg.load_string('<root BTCPP_format="4"><BehaviorTree ID="M"><Odd name="odd"/></BehaviorTree></root>')
    with pytest.raises(nt.NodeError) as info:
        tree.tick_once()
    assert info.value.path == "odd"
    assert str(info.value).startswith("odd: returned " + repr(returned))
    assert "nt.SUCCESS" in str(info.value)


def test_a_condition_returning_running_or_a_number_is_a_node_error() -> None:
    for returned in (nt.RUNNING, 1):
        reg = nt.Registry()
        reg.condition("Odd")(lambda node, robot, r=returned: r)
        tree = reg.load_string('<root BTCPP_format="4"><BehaviorTree ID="M"><Odd/></BehaviorTree></root>')
        with pytest.raises(nt.NodeError, match="Odd"):
            tree.tick_once()


def test_an_action_returning_running_is_a_node_error() -> None:
    reg = nt.Registry()
    reg.action("Slow")(lambda node, robot: nt.RUNNING)
    tree = reg.load_string('<root BTCPP_format="4"><BehaviorTree ID="M"><Slow/></BehaviorTree></root>')
    with pytest.raises(nt.NodeError, match="StatefulAction"):
        tree.tick_once()


def test_a_port_value_of_the_wrong_type_names_the_node_and_the_port() -> None:
    reg = nt.Registry()

    @reg.action("Use", ports={"count": int, "out": nt.Output(int)})
    def use(node: nt.Node, robot: Any) -> nt.Status:
        if robot == "read":
            node.input("count")
        else:
            node.output("out", "three")
        return nt.SUCCESS

    tree = reg.load_string(
        '<root BTCPP_format="4"><BehaviorTree ID="M"><Sequence>'
        "<Script code=\"c := 'many'\"/><Use name=\"use\" count=\"{c}\" out=\"{o}\"/>"
        "</Sequence></BehaviorTree></root>"
    )
    with pytest.raises(nt.NodeError) as read:
        tree.tick_once("read")
    assert read.value.path == "Sequence/use"
    assert "Sequence/use" in str(read.value) and "`count`" in str(read.value)
    assert "cannot read `many`" in str(read.value)
    with pytest.raises(nt.NodeError) as written:
        tree.tick_once("write")
    assert "Sequence/use" in str(written.value) and "`out`" in str(written.value)
    assert "declared int" in str(written.value)


def test_a_node_kept_past_its_call_refuses_to_be_used() -> None:
    reg = nt.Registry()
    kept: list[nt.Node] = []
    reg.action("Keep")(lambda node, robot: kept.append(node) or nt.SUCCESS)
    tree = reg.load_string('<root BTCPP_format="4"><BehaviorTree ID="M"><Keep/></BehaviorTree></root>')
    assert tree.tick_once() is nt.SUCCESS
    with pytest.raises(RuntimeError, match="outside its leaf's call"):
        kept[0].name


def test_ctrl_c_stops_tick_while_running_and_halts_the_tree() -> None:
    reg = nt.Registry()
    robot = {"ticks": 0, "halts": 0}

    class Forever(nt.StatefulAction):
        def on_start(self, node: nt.Node, robot: Any) -> nt.Status:
            return nt.RUNNING

        def on_running(self, node: nt.Node, robot: Any) -> nt.Status:
            robot["ticks"] += 1
            return nt.RUNNING

        def on_halted(self, node: nt.Node, robot: Any) -> None:
            robot["halts"] += 1

    reg.stateful_action("Forever", Forever)
    tree = reg.load_string(
        '<root BTCPP_format="4"><BehaviorTree ID="M"><Forever/></BehaviorTree></root>',
        clock=nt.SystemClock(),
    )
    # Python turns SIGINT into KeyboardInterrupt only if SIGINT was not ignored when it
    # started (a shell's background job ignores it): the test sets Python's handler itself.
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    timer = threading.Timer(0.2, _thread.interrupt_main)
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            # At most 20 s, should the interrupt be lost: a failure, not a hang.
            tree.tick_while_running(robot, max_ticks=4000, period=0.005)
    finally:
        timer.join()
        signal.signal(signal.SIGINT, previous)
    assert robot["ticks"] > 0
    assert robot["halts"] == 1
    assert [s for _, s in tree.statuses()] == [nt.Status.IDLE]


def test_an_async_leaf_that_raises_after_awaiting_is_a_node_error() -> None:
    reg = nt.Registry()

    @reg.action("Late")
    async def late(node: nt.Node, robot: Any) -> nt.Status:
        await nt.next_tick()
        raise KeyError("gone")

    @reg.action("Odd")
    async def odd(node: nt.Node, robot: Any) -> Any:
        return "done"

    tree = reg.load_string('<root BTCPP_format="4"><BehaviorTree ID="M"><Late/></BehaviorTree></root>')
    assert tree.tick_once() is nt.RUNNING
    with pytest.raises(nt.NodeError) as info:
        tree.tick_once()
    assert info.value.path == "Late" and isinstance(info.value.__cause__, KeyError)
    assert tree.tick_once() is nt.RUNNING  # afresh: a new coroutine
    odd_tree = reg.load_string('<root BTCPP_format="4"><BehaviorTree ID="M"><Odd/></BehaviorTree></root>')
    with pytest.raises(nt.NodeError, match="returned 'done'"):
        odd_tree.tick_once()


def test_a_mistyped_port_gets_the_nearest_declared_name() -> None:
    reg = nt.Registry()
    reg.action("MoveTo", ports={"goal": str, "speed": float})(lambda node, robot: nt.SUCCESS)
    with pytest.raises(nt.LoadError) as raised:
        reg.load_string(
            '<root BTCPP_format="4"><BehaviorTree ID="M"><MoveTo gaol="dock"/></BehaviorTree></root>'
        )
    assert "unknown port `gaol` on `MoveTo` (did you mean `goal`?)" in str(raised.value)


def test_an_exception_in_on_halted_is_raised_from_halt_once_the_tree_is_halted() -> None:
    reg = nt.Registry()
    halts: list[str] = []

    class Clumsy(nt.StatefulAction):
        def on_start(self, node: nt.Node, robot: Any) -> nt.Status:
            return nt.RUNNING

        def on_running(self, node: nt.Node, robot: Any) -> nt.Status:
            return nt.RUNNING

        def on_halted(self, node: nt.Node, robot: Any) -> None:
            halts.append("clumsy")
            raise ValueError("dropped the tool")

    class Tidy(nt.StatefulAction):
        def on_start(self, node: nt.Node, robot: Any) -> nt.Status:
            return nt.RUNNING

        def on_running(self, node: nt.Node, robot: Any) -> nt.Status:
            return nt.RUNNING

        def on_halted(self, node: nt.Node, robot: Any) -> None:
            halts.append("tidy")

    reg.stateful_action("Clumsy", Clumsy)
    reg.stateful_action("Tidy", Tidy)
    tree = reg.load_string(
        '<root BTCPP_format="4"><BehaviorTree ID="M">'
        '<Parallel success_count="-1" failure_count="1"><Clumsy/><Tidy/></Parallel>'
        "</BehaviorTree></root>"
    )
    assert tree.tick_once() is nt.RUNNING
    with pytest.raises(ValueError, match="dropped the tool"):
        tree.halt()
    # Halted all the same: both actions heard of it, every node is Idle.
    assert sorted(halts) == ["clumsy", "tidy"]
    assert all(status is nt.Status.IDLE for _, status in tree.statuses())
    tree.halt()
    assert len(halts) == 2


def test_a_save_state_that_raises_makes_tree_save_state_raise() -> None:
    reg = nt.Registry()

    class Secretive(nt.StatefulAction):
        def on_start(self, node: nt.Node, robot: Any) -> nt.Status:
            return nt.RUNNING

        def on_running(self, node: nt.Node, robot: Any) -> nt.Status:
            return nt.RUNNING

        def save_state(self) -> bytes:
            raise OSError("cannot reach the arm")

    reg.stateful_action("Secretive", Secretive)
    tree = reg.load_string('<root BTCPP_format="4"><BehaviorTree ID="M"><Secretive/></BehaviorTree></root>')
    assert tree.tick_once() is nt.RUNNING
    with pytest.raises(OSError, match="cannot reach the arm"):
        tree.save_state()
