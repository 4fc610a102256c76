#!/usr/bin/env python3
"""tree1111 from Python: NeuroTree's package beside py_trees and behaviortreepy, in one process.

Four comparisons, each printed as one JSON line and summed up in a table at the end:

1. python leaves: tree1111.xml loaded by `neurotree` with `Succ`/`Fail` registered as
   Python conditions, beside the same tree in py_trees 2.6 (stock `Success`/`Failure`
   behaviours, built as `pytrees_tree1111.py` builds it) and the same XML in behaviortreepy
   with `Succ`/`Fail` registered as Python conditions (`register_simple_condition`).
   Every leaf is Python code in all three.
2. built-ins: the tree with `AlwaysSuccess`/`AlwaysFailure` leaves, ticked from Python one
   call per tick, beside the same ticked by Rust in a loop (`Tree.tick_times`), which is
   what one call costs from Python.
3. one leaf call: a tree of one Python condition, ticked from Python, less the same tree
   with a built-in leaf: what entering Python for a leaf costs.

Usage: python_tree1111.py [TREE_XML] [--ticks N] [--pytrees-ticks N]
Needs `pip install ./crates/neurotree-py py_trees==2.6.0 behaviortreepy==0.1.4`; a library
that is not installed is left out, with a note.
"""

from __future__ import annotations

import argparse
import importlib.util
import json
import os
import platform
import sys
import time
import xml.etree.ElementTree as ET
from typing import Callable, Optional

import neurotree as nt

HERE = os.path.dirname(os.path.abspath(__file__))
DEFAULT_TREE = os.path.normpath(os.path.join(HERE, "..", "..", "..", "corpus", "bench", "tree1111.xml"))
NODES = 1111


def timed(tick: Callable[[], object], ticks: int, warmup: int, expected: object) -> float:
    """Nanoseconds per call of `tick`, the fastest of three rounds (each checked)."""
    for _ in range(warmup):
        if tick() != expected:
            raise SystemExit(f"a warm-up tick returned {tick()!r}, not {expected!r}")
    best = float("inf")
    for _ in range(3):
        t0 = time.perf_counter_ns()
        for _ in range(ticks):
            tick()
        best = min(best, (time.perf_counter_ns() - t0) / ticks)
        if tick() != expected:
            raise SystemExit("a tick returned another status")
    return best


def report(name: str, ns_per_tick: float, nodes: int = NODES) -> dict[str, object]:
    line = {"name": name, "ns_per_tick": round(ns_per_tick, 1), "ns_per_node": round(ns_per_tick / nodes, 2)}
    print(json.dumps(line, separators=(",", ":")), flush=True)
    return line


def neurotree_python_leaves(xml: str, ticks: int) -> float:
    reg = nt.Registry()
    reg.condition("Succ")(lambda node, robot: True)
    reg.condition("Fail")(lambda node, robot: False)
    tree = reg.load_string(xml)
    return timed(tree.tick_once, ticks, ticks // 10, nt.SUCCESS)


def neurotree_builtins(xml: str, ticks: int) -> tuple[float, float]:
    xml = xml.replace("<Succ/>", "<AlwaysSuccess/>").replace("<Fail/>", "<AlwaysFailure/>")
    tree = nt.Registry().load_string(xml)
    from_python = timed(tree.tick_once, ticks, ticks // 10, nt.SUCCESS)
    best = float("inf")
    for _ in range(3):
        t0 = time.perf_counter_ns()
        tree.tick_times(ticks)
        best = min(best, (time.perf_counter_ns() - t0) / ticks)
    return from_python, best


def one_leaf_call(ticks: int) -> float:
    reg = nt.Registry()
    reg.condition("Py")(lambda node, robot: True)
    python = reg.load_string('<root BTCPP_format="4"><BehaviorTree ID="M"><Py/></BehaviorTree></root>')
    builtin = reg.load_string('<root BTCPP_format="4"><BehaviorTree ID="M"><AlwaysSuccess/></BehaviorTree></root>')
    with_leaf = timed(python.tick_once, ticks, ticks // 10, nt.SUCCESS)
    without = timed(builtin.tick_once, ticks, ticks // 10, nt.SUCCESS)
    return with_leaf - without


def pytrees(xml_path: str, ticks: int) -> Optional[float]:
    try:
        import py_trees
    except ImportError:
        print("py_trees is not installed: left out", file=sys.stderr)
        return None
    spec = importlib.util.spec_from_file_location("pytrees_tree1111", os.path.join(HERE, "pytrees_tree1111.py"))
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    root_xml = ET.parse(xml_path).getroot()
    trees = root_xml.findall("BehaviorTree")
    main = root_xml.get("main_tree_to_execute")
    bt_elem = next((t for t in trees if t.get("ID") == main), trees[0])
    root = module.build(bt_elem[0], [0])

    def tick() -> object:
        root.tick_once()
        return root.status

    return timed(tick, ticks, max(ticks // 10, 5), py_trees.common.Status.SUCCESS)


def behaviortreepy(xml: str, ticks: int) -> Optional[float]:
    try:
        import behaviortreepy as bt
    except ImportError:
        print("behaviortreepy is not installed: left out", file=sys.stderr)
        return None
    factory = bt.BehaviorTreeFactory()
    success, failure = bt.NodeStatus.SUCCESS, bt.NodeStatus.FAILURE
    factory.register_simple_condition("Succ", lambda node: success)
    factory.register_simple_condition("Fail", lambda node: failure)
    tree = factory.create_tree_from_text(xml)
    return timed(tree.tick_exactly_once, ticks, ticks // 10, success)


def main() -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("tree", nargs="?", default=os.environ.get("TREE1111", DEFAULT_TREE))
    ap.add_argument("--ticks", type=int, default=2000)
    ap.add_argument("--pytrees-ticks", type=int, default=100)
    args = ap.parse_args()
    with open(args.tree, encoding="utf-8") as f:
        xml = f.read()

    print(f"# python {platform.python_version()}, {platform.machine()}", flush=True)
    ours = report("neurotree, python leaves", neurotree_python_leaves(xml, args.ticks))
    others = []
    py = pytrees(args.tree, args.pytrees_ticks)
    if py is not None:
        others.append(report("py_trees 2.6, python leaves", py))
    cpp = behaviortreepy(xml, args.ticks)
    if cpp is not None:
        others.append(report("behaviortreepy (BT.CPP 4.8), python leaves", cpp))
    from_python, from_rust = neurotree_builtins(xml, args.ticks * 5)
    report("neurotree, built-ins, a tick_once call from python", from_python)
    report("neurotree, built-ins, ticked by rust (tick_times)", from_rust)
    leaf = one_leaf_call(args.ticks * 50)
    print(json.dumps({"name": "one python leaf call", "ns": round(leaf, 1)}), flush=True)

    print()
    print(f"{'python leaves':45} {'ns/node':>9} {'vs neurotree':>13}")
    for line in [ours, *others]:
        ratio = float(str(line["ns_per_node"])) / float(str(ours["ns_per_node"]))
        print(f"{line['name']:45} {line['ns_per_node']:>9} {ratio:>12.1f}x")
    return 0


if __name__ == "__main__":
    sys.exit(main())
