#!/usr/bin/env python3
"""tree1111 benchmark for py_trees.

Builds the tree of tree1111.xml with py_trees: <Sequence> ->
composites.Sequence(memory=False), <Fallback> -> composites.Selector(memory=False),
<Succ/> -> behaviours.Success, <Fail/> -> behaviours.Failure, then calls
`root.tick_once()` repeatedly (the bare tick: no BehaviourTree pre/post tick
handlers or visitors).

Memory semantics: in py_trees, `memory` only matters when a child returns
RUNNING. memory=True resumes at the RUNNING child on the next tick (which is
what BT.CPP's Sequence/Fallback do); memory=False re-evaluates from the first
child every tick (like BT.CPP's ReactiveSequence/ReactiveFallback). No leaf of
tree1111 ever returns RUNNING, so both settings visit exactly the same nodes
here; memory=False is used because it is the plain "re-check everything"
mode. Note also that a py_trees Sequence/Selector that was not RUNNING calls
stop(INVALID) on its non-INVALID children at the start of each tick (BT.CPP
similarly resets children to IDLE when a control node finishes), and every
node goes through initialise()/update()/stop() and Python generators, so this
measures pure-Python per-node overhead.

Usage: pytrees_tree1111.py [TREE_XML] [--ticks N] [--warmup N]
TREE_XML defaults to $TREE1111, then to the repository's corpus/bench/tree1111.xml
relative to this file.

Prints one JSON line:
{"name":"py_trees","ticks":N,"ns_per_tick":X,"nodes_per_tick":1111,"ns_per_node":Y}
"""

import argparse
import json
import os
import sys
import time
import xml.etree.ElementTree as ET

import py_trees

HERE = os.path.dirname(os.path.abspath(__file__))
DEFAULT_TREE = os.path.normpath(os.path.join(HERE, "..", "..", "..", "corpus", "bench", "tree1111.xml"))


def build(elem: ET.Element, counter: list) -> py_trees.behaviour.Behaviour:
    counter[0] += 1
    name = f"{elem.tag}{counter[0]}"
    if elem.tag == "Succ":
        return py_trees.behaviours.Success(name=name)
    if elem.tag == "Fail":
        return py_trees.behaviours.Failure(name=name)
    children = [build(c, counter) for c in elem]
    if elem.tag == "Sequence":
        return py_trees.composites.Sequence(name=name, memory=False, children=children)
    if elem.tag == "Fallback":
        return py_trees.composites.Selector(name=name, memory=False, children=children)
    raise SystemExit(f"pytrees: unsupported node <{elem.tag}>")


def main() -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("tree", nargs="?", default=os.environ.get("TREE1111", DEFAULT_TREE))
    ap.add_argument("--ticks", type=int, default=300)
    ap.add_argument("--warmup", type=int, default=30)
    args = ap.parse_args()

    xml_root = ET.parse(args.tree).getroot()
    trees = xml_root.findall("BehaviorTree")
    main_id = xml_root.get("main_tree_to_execute")
    bt_elem = next((t for t in trees if t.get("ID") == main_id), trees[0])
    if len(bt_elem) != 1:
        raise SystemExit("pytrees: <BehaviorTree> must have exactly one root node")
    counter = [0]
    root = build(bt_elem[0], counter)
    nodes = counter[0]
    SUCCESS = py_trees.common.Status.SUCCESS

    # Sanity check: one tick must visit every node (all of them end up with a
    # non-INVALID status) and the root must succeed.
    root.tick_once()
    visited = sum(1 for n in root.iterate() if n.status != py_trees.common.Status.INVALID)
    if root.status != SUCCESS or visited != nodes:
        print(f"pytrees: root={root.status}, visited {visited}/{nodes}", file=sys.stderr)
        return 1

    tick = root.tick_once
    for _ in range(args.warmup):
        tick()
        if root.status != SUCCESS:
            print(f"pytrees: root returned {root.status}, expected SUCCESS", file=sys.stderr)
            return 1

    ok = True
    t0 = time.perf_counter_ns()
    for _ in range(args.ticks):
        tick()
        ok &= root.status == SUCCESS
    elapsed = time.perf_counter_ns() - t0
    if not ok:
        print("pytrees: a tick did not return SUCCESS", file=sys.stderr)
        return 1

    ns_tick = elapsed / args.ticks
    print(json.dumps({
        "name": "py_trees",
        "ticks": args.ticks,
        "ns_per_tick": round(ns_tick, 1),
        "nodes_per_tick": nodes,
        "ns_per_node": round(ns_tick / nodes, 3),
    }, separators=(",", ":")))
    return 0


if __name__ == "__main__":
    sys.exit(main())
