#!/bin/sh
# Draws the pictures in this folder again with the `neurotree` binary of this workspace.
# Run from the repository root; the trees come from its corpus/ folder.
set -eu
corpus=corpus
images=docs/images
neurotree="cargo run --quiet -p neurotree-cli --"
# `run` exits 3 when --max-ticks stops a run still RUNNING, as these dry runs are meant to.
stopped() { [ "$1" -eq 3 ]; }

# BehaviorTree.CPP's crossdoor tutorial, dry-run with mocks: the door is closed, opening
# it fails, the lock gives way at the second attempt, and walking through is under way.
crossdoor=$corpus/btcpp/examples/examples__t05_crossdoor__01.xml
$neurotree run "$crossdoor" --tree MainTree --mock-unknown \
  --mock IsDoorClosed=SUCCESS --mock OpenDoor=FAILURE --mock PickLock=FAILURE,SUCCESS \
  --mock PassThroughDoor=RUNNING --max-ticks 2 --trace > "$images/crossdoor.trace.jsonl" ||
  stopped $?
$neurotree show "$crossdoor" --tree MainTree --model "$images/crossdoor_nodes.xml" \
  --trace "$images/crossdoor.trace.jsonl" -o "$images/crossdoor.svg"

# The Nav2 navigator that replans at 1 Hz and recovers, its node types from Nav2's model,
# after two ticks of a dry run in which following the path is under way.
nav2=$corpus/nav2/navigate_to_pose_w_replanning_and_recovery.xml
$neurotree run "$nav2" --mock-unknown --mock FollowPath=RUNNING --set "goal=3;4;0" \
  --max-ticks 2 --trace > "$images/navigate_to_pose.trace.jsonl" || stopped $?
$neurotree show "$nav2" --model "$corpus/nav2/nav2_tree_nodes.xml" \
  --trace "$images/navigate_to_pose.trace.jsonl" -o "$images/navigate_to_pose.svg"
