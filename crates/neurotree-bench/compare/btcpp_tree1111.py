#!/usr/bin/env python3
"""tree1111 benchmark for BehaviorTree.CPP 4 through the `behaviortreepy` bindings.

The leaves of tree1111.xml (`<Succ/>`, `<Fail/>`) are replaced by BT.CPP's
built-in `AlwaysSuccess` / `AlwaysFailure` nodes, so a whole tick runs in C++:
Python is entered once per tick (the `tick_exactly_once()` call), not once per
node, and that call overhead is amortized over the 1111 nodes.

Usage: btcpp_tree1111.py [TREE_XML] [--ticks N] [--warmup N]
TREE_XML defaults to $TREE1111, then to the repository's corpus/bench/tree1111.xml
relative to this file.

Prints one JSON line:
{"name":"btcpp","ticks":N,"ns_per_tick":X,"nodes_per_tick":1111,"ns_per_node":Y}
"""

import argparse
import json
import os
import sys
import time
import xml.etree.ElementTree as ET

import behaviortreepy as bt

HERE = os.path.dirname(os.path.abspath(__file__))
DEFAULT_TREE = os.path.normpath(os.path.join(HERE, "..", "..", "..", "corpus", "bench", "tree1111.xml"))


def count_nodes(xml_text: str) -> int:
    """Nodes of the main tree: every element below <BehaviorTree>."""
    root = ET.fromstring(xml_text)
    trees = root.findall("BehaviorTree")
    main = root.get("main_tree_to_execute")
    tree = next((t for t in trees if t.get("ID") == main), trees[0])
    return sum(1 for _ in tree.iter()) - 1


def main() -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("tree", nargs="?", default=os.environ.get("TREE1111", DEFAULT_TREE))
    ap.add_argument("--ticks", type=int, default=5000)
    ap.add_argument("--warmup", type=int, default=500)
    args = ap.parse_args()

    with open(args.tree, encoding="utf-8") as f:
        xml_text = f.read()
    nodes = count_nodes(xml_text)
    xml_text = xml_text.replace("<Succ/>", "<AlwaysSuccess/>").replace("<Fail/>", "<AlwaysFailure/>")

    factory = bt.BehaviorTreeFactory()
    tree = factory.create_tree_from_text(xml_text)
    SUCCESS = bt.NodeStatus.SUCCESS
    tick = tree.tick_exactly_once

    for _ in range(args.warmup):
        status = tick()
        if status != SUCCESS:
            print(f"btcpp: root returned {status}, expected SUCCESS", file=sys.stderr)
            return 1

    # Every status is checked; collect them in a list so the comparison is
    # outside the timed loop body's critical path but still verified.
    statuses = [None] * args.ticks
    t0 = time.perf_counter_ns()
    for i in range(args.ticks):
        statuses[i] = tick()
    elapsed = time.perf_counter_ns() - t0
    bad = [s for s in statuses if s != SUCCESS]
    if bad:
        print(f"btcpp: {len(bad)} ticks did not return SUCCESS (e.g. {bad[0]})", file=sys.stderr)
        return 1

    ns_tick = elapsed / args.ticks
    print(json.dumps({
        "name": "btcpp",
        "ticks": args.ticks,
        "ns_per_tick": round(ns_tick, 1),
        "nodes_per_tick": nodes,
        "ns_per_node": round(ns_tick / nodes, 3),
    }, separators=(",", ":")))
    return 0


if __name__ == "__main__":
    sys.exit(main())
