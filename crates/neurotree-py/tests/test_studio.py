"""The studio watches a tree ticked from Python: the page's pause, step and blackboard edits
reach Python leaves. The test speaks the page's protocol (crates/neurotree-studio/PROTOCOL.md)
over the WebSocket a page uses."""

from __future__ import annotations

import json
import threading
import urllib.request
from typing import Any

import neurotree as nt
import pytest

websocket = pytest.importorskip("websocket")


def receive(ws: Any, kind: str) -> dict[str, Any]:
    """The next message of type `kind`, skipping others."""
    while True:
        message = json.loads(ws.recv())
        if message["type"] == kind:
            return dict(message)


def test_pause_step_and_edits_reach_python_leaves() -> None:
    reg = nt.Registry()
    seen: list[int] = []

    class Watcher(nt.StatefulAction):
        ports = {"v": int}

        def on_start(self, node: nt.Node, robot: Any) -> nt.Status:
            seen.append(node.input("v"))
            return nt.RUNNING

        def on_running(self, node: nt.Node, robot: Any) -> nt.Status:
            seen.append(node.input("v"))
            return nt.RUNNING

    reg.stateful_action("Watcher", Watcher)
    tree = reg.load_string('<root BTCPP_format="4"><BehaviorTree ID="M"><Watcher v="{goal}"/></BehaviorTree></root>')
    tree.blackboard["goal"] = 1
    url = nt.studio.watch(tree)
    assert url.startswith("http://127.0.0.1:")
    with urllib.request.urlopen(url, timeout=10) as page:
        assert b"<html" in page.read().lower()

    ws = websocket.create_connection(url.replace("http://", "ws://") + "ws", timeout=10)
    try:
        hello = receive(ws, "hello")
        assert hello["run"] is not None
        assert tree.tick_once() is nt.RUNNING
        assert seen == [1]

        ws.send(json.dumps({"type": "pause"}))
        # The server reads a page's messages in order: once it answers the breakpoint list
        # after the pause, the pause is in force before the tick below starts.
        ws.send(json.dumps({"type": "breakpoint", "node": 0, "when": "off"}))
        receive(ws, "breakpoints")
        results: list[nt.Status] = []
        ticking = threading.Thread(target=lambda: results.append(tree.tick_once()))
        ticking.start()
        receive(ws, "paused")
        ticking.join(0.3)
        assert ticking.is_alive() and seen == [1], "a paused run does not tick"

        ws.send(json.dumps({"type": "set", "scope": 0, "key": "goal", "value": 5}))
        receive(ws, "blackboards")
        ws.send(json.dumps({"type": "step"}))
        ticking.join(10)
        assert not ticking.is_alive()
        assert results == [nt.RUNNING]
        assert seen == [1, 5], "the step ticked once, with the page's edit"
        assert tree.blackboard["goal"] == 5

        ws.send(json.dumps({"type": "continue"}))
        receive(ws, "resumed")
        assert tree.tick_once() is nt.RUNNING
        assert seen == [1, 5, 5]
    finally:
        ws.close()
