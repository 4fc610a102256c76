#!/usr/bin/env python3
"""BehaviorTree.CPP's side of the differential test (`tests/differential.rs`).

Runs a batch of cases through BehaviorTree.CPP 4 itself, by way of the `behaviortreepy`
bindings (0.1.4, which bundle BehaviorTree.CPP 4.8.2), and prints what it did as JSON
lines, one per case.

Input: a file of JSON lines, one case each:

    {"id": 3, "xml": "<root ...>", "scripts": {"n2": "RRS", ...}, "ops": "TEHT"}

Every node of the XML is named `n<i>`, i its pre-order index. The leaves `Act` (a
stateful action), `Sync` (a sync action) and `Cond` (a condition) play the script of
their name: the k-th call returns the k-th letter (S, F, R), the last one repeating. Each
letter of `ops` is one step: T = `tickOnce`, E = `tickExactlyOnce`, H = `haltTree`.

Output, one line per case:

    {"id": 3, "steps": [{"status": "RUNNING", "changes": [["n0", "IDLE", "RUNNING"], ...],
                         "calls": [["n2", "start", "RUNNING"], ...],
                         "ticks": {"n0": 1, ...}, "stale_wake": false}, ...]}

A step whose tick raised has `"error": message` instead of a status, and ends the case.

How each thing is observed, since the bindings have no tree observer:
- `changes`: every stored-status change, in order, from BehaviorTree.CPP's own
  `StdCoutLogger`, whose C++ `printf` lines are caught by pointing file descriptor 1 at a
  temporary file (this script writes its JSON to a copy of the original descriptor).
- `calls`: the scripted leaves' callbacks, in order (`start`, `running`, `halted` for
  `Act`; `tick` for `Sync` and `Cond`), each with what it returned.
- `ticks`: per node, the ticks that began with the node Idle or Running, counted by a
  `_while="t<i> += 1; true"` precondition added to every node here: BehaviorTree.CPP
  evaluates `_while` in `executeTick` exactly when the stored status is Idle or Running
  (not when a node is ticked again while still Success or Failure).
- `stale_wake`: before a `tickOnce`, whether a wake-up signal from an earlier call was
  still pending. It is cleared (with `Tree::sleep(0)`, which consumes it): NeuroTree counts
  a wake-up only within the call that received it (a documented difference), so the
  pending signal would only add a pass that NeuroTree deliberately does not make.

A leaf called more than CALL_BUDGET times in one step makes the tick throw: the step is
reported as the error "runaway", so that a `tickOnce` that never ends cannot hang the batch.
"""

import json
import os
import re
import sys
import tempfile
import xml.etree.ElementTree as ET

import behaviortreepy as bt

CALL_BUDGET = 5000
S = bt.NodeStatus
OUTCOME = {"S": S.SUCCESS, "F": S.FAILURE, "R": S.RUNNING}
NAME = {
    S.SUCCESS: "SUCCESS",
    S.FAILURE: "FAILURE",
    S.RUNNING: "RUNNING",
    S.IDLE: "IDLE",
    S.SKIPPED: "SKIPPED",
}
ANSI = re.compile(r"\x1b\[[0-9;]*m")
LINE = re.compile(r"^\[[^\]]*\]: (\S+)\s+(\w+) -> (\w+)$")


class Leaves:
    """The scripts of the current case, the calls made so far, and this step's calls."""

    def __init__(self):
        self.scripts = {}
        self.counts = {}
        self.events = []
        self.step_calls = 0
        self.runaway = False
        self.recording = False

    def reset(self, scripts):
        self.scripts = scripts
        self.counts = {name: 0 for name in scripts}
        self.events = []
        self.step_calls = 0
        self.runaway = False
        self.recording = True

    def play(self, node, what):
        if not self.recording:
            return S.FAILURE
        name = node.name()
        self.step_calls += 1
        if self.step_calls > CALL_BUDGET:
            # The bindings turn a Python exception into FAILURE, which need not end the
            # tick (a RetryUntilSuccessful would go on); IDLE makes BehaviorTree.CPP throw
            # (a node may not return it), and that ends the tick with an error.
            self.runaway = True
            return S.IDLE
        k = self.counts[name]
        self.counts[name] = k + 1
        script = self.scripts[name]
        letter = script[min(k, len(script) - 1)]
        self.events.append([name, what, NAME[OUTCOME[letter]]])
        return OUTCOME[letter]

    def halted(self, node):
        if self.recording:
            self.events.append([node.name(), "halted", None])


def factory(leaves):
    f = bt.BehaviorTreeFactory()
    f.register_simple_stateful_action(
        "Act",
        lambda n: leaves.play(n, "start"),
        lambda n: leaves.play(n, "running"),
        leaves.halted,
    )
    f.register_simple_action("Sync", lambda n: leaves.play(n, "tick"))
    f.register_simple_condition("Cond", lambda n: leaves.play(n, "tick"))
    return f


def instrument(xml_text):
    """The case's XML with a counting `_while` on every node; the node names."""
    root = ET.fromstring(xml_text)
    names = []
    for tree in root.findall("BehaviorTree"):
        for el in tree.iter():
            if el is tree:
                continue
            name = el.get("name")
            names.append(name)
            el.set("_while", "t_%s += 1; true" % name)
    return ET.tostring(root, encoding="unicode"), names


class Capture:
    """C stdout (file descriptor 1) redirected into a temporary file, read step by step."""

    def __init__(self):
        sys.stdout.flush()
        self.saved = os.dup(1)
        # O_APPEND, so that after a truncation the logger writes from the start again.
        fd, path = tempfile.mkstemp(prefix="btcpp-changes-")
        os.close(fd)
        self.fd = os.open(path, os.O_RDWR | os.O_APPEND)
        os.unlink(path)
        os.dup2(self.fd, 1)
        self.out = os.fdopen(self.saved, "w", buffering=1)

    def take(self):
        end = os.lseek(self.fd, 0, os.SEEK_END)
        data = os.pread(self.fd, end, 0)
        os.ftruncate(self.fd, 0)
        changes = []
        for raw in data.decode("utf-8", "replace").splitlines():
            m = LINE.match(ANSI.sub("", raw).strip())
            if m:
                changes.append([m.group(1), m.group(2), m.group(3)])
            elif raw.strip():
                changes.append(["?", "unparsed", raw])
        return changes


def run_case(case, fac, leaves, capture):
    leaves.reset(case["scripts"])
    xml_text, names = instrument(case["xml"])
    bb = bt.Blackboard.create()
    for name in names:
        bb.set_int("t_" + name, 0)
    steps = []
    try:
        tree = fac.create_tree_from_text(xml_text, bb)
    except Exception as e:  # noqa: BLE001 - reported, compared with NeuroTree's load
        return {"id": case["id"], "load_error": str(e), "steps": []}
    logger = bt.StdCoutLogger(tree)
    capture.take()
    before = {name: 0 for name in names}
    for op in case["ops"]:
        leaves.events = []
        leaves.step_calls = 0
        step = {}
        try:
            if op == "T":
                step["stale_wake"] = bool(tree.sleep(0))
                step["status"] = NAME[tree.tick_once()]
            elif op == "E":
                step["status"] = NAME[tree.tick_exactly_once()]
            else:
                tree.halt_tree()
                step["status"] = None
        except Exception as e:  # noqa: BLE001 - a throwing node ends the case
            step["error"] = "runaway" if leaves.runaway else str(e)
        logger.flush()
        step["changes"] = capture.take()
        step["calls"] = leaves.events
        ticks = {}
        for name in names:
            now = bb.get_int("t_" + name)
            if now != before[name]:
                ticks[name] = now - before[name]
            before[name] = now
        step["ticks"] = ticks
        steps.append(step)
        if "error" in step:
            break
    # A tree halts itself when it is destroyed, which Python may do during a later case:
    # halt it now, unrecorded, so that no callback of this case lands in the next one.
    leaves.recording = False
    try:
        tree.halt_tree()
    except Exception:  # noqa: BLE001 - the case is over
        pass
    del logger
    del tree
    capture.take()
    return {"id": case["id"], "steps": steps}


def main():
    if len(sys.argv) != 2:
        print("usage: btcpp_run.py CASES.jsonl", file=sys.stderr)
        return 2
    leaves = Leaves()
    fac = factory(leaves)
    capture = Capture()
    with open(sys.argv[1], encoding="utf-8") as f:
        for line in f:
            if line.strip():
                result = run_case(json.loads(line), fac, leaves, capture)
                capture.out.write(json.dumps(result, separators=(",", ":")) + "\n")
    capture.out.flush()
    return 0


if __name__ == "__main__":
    sys.exit(main())
