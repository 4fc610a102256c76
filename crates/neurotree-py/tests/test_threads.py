"""The GIL is released while the engine ticks; a tree may be ticked from any thread."""

from __future__ import annotations

import threading
from typing import Any

import neurotree as nt
import pytest

# A million cycles of a built-in leaf: one tick_once of pure Rust work.
BUSY = (
    '<root BTCPP_format="4"><BehaviorTree ID="M">'
    '<Repeat num_cycles="1000000"><AlwaysSuccess/></Repeat></BehaviorTree></root>'
)


def test_other_python_threads_run_while_built_in_nodes_tick() -> None:
    tree = nt.Registry().load_string(BUSY)
    count = [0]
    stop = threading.Event()
    started = threading.Event()

    def spin() -> None:
        started.set()
        while not stop.is_set():
            count[0] += 1

    spinner = threading.Thread(target=spin)
    spinner.start()
    started.wait()
    try:
        before = count[0]
        assert tree.tick_once() is nt.SUCCESS
        during = count[0] - before
    finally:
        stop.set()
        spinner.join()
    # With the GIL held through the tick, the spinner could not have counted at all.
    assert during > 1000, during


def test_a_tree_built_on_one_thread_ticks_on_another() -> None:
    reg = nt.Registry()
    seen: list[str] = []

    @reg.action("Where")
    def where(node: nt.Node, robot: Any) -> nt.Status:
        seen.append(threading.current_thread().name)
        return nt.SUCCESS

    tree = reg.load_string('<root BTCPP_format="4"><BehaviorTree ID="M"><Where/></BehaviorTree></root>')
    results: list[nt.Status] = []
    worker = threading.Thread(target=lambda: results.append(tree.tick_once()), name="worker")
    worker.start()
    worker.join()
    assert results == [nt.SUCCESS]
    assert seen == ["worker"]
    assert tree.tick_once() is nt.SUCCESS
    assert seen == ["worker", threading.current_thread().name]


def test_threads_ticking_one_tree_take_turns() -> None:
    reg = nt.Registry()
    inside = [0]
    overlaps = [0]
    calls = [0]

    @reg.action("Count")
    def count(node: nt.Node, robot: Any) -> nt.Status:
        inside[0] += 1
        if inside[0] > 1:
            overlaps[0] += 1
        calls[0] += 1
        inside[0] -= 1
        return nt.SUCCESS

    tree = reg.load_string(
        '<root BTCPP_format="4"><BehaviorTree ID="M"><Sequence>'
        '<Repeat num_cycles="2000"><AlwaysSuccess/></Repeat><Count/></Sequence></BehaviorTree></root>'
    )

    # Ticks finished so far, under `turn`: a thread refused waits for the tick that was
    # under way to finish, rather than spinning.
    turn = threading.Condition()
    finished = [0]

    def work() -> None:
        done = 0
        while done < 200:
            with turn:
                seen = finished[0]
            # A tick while another thread's is under way is refused at once: take turns.
            try:
                assert tree.tick_once() is nt.SUCCESS
            except nt.TreeBusy:
                with turn:
                    turn.wait_for(lambda: finished[0] != seen)
                continue
            done += 1
            with turn:
                finished[0] += 1
                turn.notify_all()

    threads = [threading.Thread(target=work) for _ in range(4)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert calls[0] == 800
    assert overlaps[0] == 0


def test_a_leaf_reaching_its_own_tree_is_told_to_use_its_node() -> None:
    reg = nt.Registry()
    holder: dict[str, nt.Tree] = {}

    @reg.action("Peek")
    def peek(node: nt.Node, robot: Any) -> nt.Status:
        holder["tree"].blackboard["x"]
        return nt.SUCCESS

    tree = reg.load_string('<root BTCPP_format="4"><BehaviorTree ID="M"><Peek/></BehaviorTree></root>')
    holder["tree"] = tree
    with pytest.raises(nt.NodeError) as info:
        tree.tick_once()
    assert isinstance(info.value.__cause__, nt.TreeBusy)
    assert "node.get" in str(info.value.__cause__)


def test_a_tick_from_another_thread_during_a_tick_is_refused_at_once() -> None:
    reg = nt.Registry()
    refused: list[nt.TreeBusy] = []
    holder: dict[str, nt.Tree] = {}

    @reg.action("AskHelper")
    def ask_helper(node: nt.Node, robot: Any) -> nt.Status:
        # A helper thread that ticks this very tree, waited for by the leaf: waiting for
        # the tick to end would wait for ever.
        def helper() -> None:
            try:
                holder["tree"].tick_once()
            except nt.TreeBusy as e:
                refused.append(e)

        thread = threading.Thread(target=helper)
        thread.start()
        thread.join()
        return nt.SUCCESS

    tree = reg.load_string('<root BTCPP_format="4"><BehaviorTree ID="M"><AskHelper/></BehaviorTree></root>')
    holder["tree"] = tree
    assert tree.tick_once() is nt.SUCCESS
    assert len(refused) == 1
    assert "another thread" in str(refused[0])
    assert isinstance(refused[0], RuntimeError)
    # Once the tick is done, the tree is ticked from any thread again (whose leaf's helper
    # is refused in turn).
    outcomes: list[nt.Status] = []
    other = threading.Thread(target=lambda: outcomes.append(tree.tick_once()))
    other.start()
    other.join()
    assert outcomes == [nt.SUCCESS]
    assert len(refused) == 2
