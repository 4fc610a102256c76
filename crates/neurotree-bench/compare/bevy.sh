#!/usr/bin/env bash
# NeuroTree's Bevy plugin beside bevy_behave, on bevy_behave's own chase scenario: enemies
# wait until the player is in sight, chase it, nap after a catch (see bevy_behave/src/main.rs
# and crates/neurotree-bevy/examples/chase.rs). Both are built in release and run one after
# the other at each crowd size, on this machine, and a table of frame times is printed.
# NeuroTree runs twice: ticking every enemy every frame, as bevy_behave's leaves check every
# frame, and with a level-of-detail hook (`--lod`: enemies far from the player tick every
# 8th frame, which changes what they see in no frame).
#
# Usage: bash crates/neurotree-bench/compare/bevy.sh            (from any directory)
# Environment:
#   AGENTS="10000 100000 1000000"   crowd sizes
#   FRAMES=100                      timed frames per run (after one untimed first frame)
#   SPACING=40                      field side per square root of an enemy: 40, few see the
#                                   player; 1, many chase, catch and nap in turn
#   CARGO_TARGET_DIR                where to build (default: <repo>/target); bevy_behave's
#                                   crate builds in its compare-bevy-behave/ subdirectory
set -euo pipefail

HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
REPO="$(cd "$HERE/../../.." && pwd)"
AGENTS="${AGENTS:-10000 100000 1000000}"
FRAMES="${FRAMES:-100}"
SPACING="${SPACING:-40}"
TARGET="${CARGO_TARGET_DIR:-$REPO/target}"

echo "building NeuroTree's side (Bevy 0.20) ..." >&2
(cd "$REPO" && CARGO_TARGET_DIR="$TARGET" cargo build --quiet --release -p neurotree-bevy --example chase)
echo "building bevy_behave's side (bevy_behave 0.5, Bevy 0.18) ..." >&2
(cd "$HERE/bevy_behave" && cargo build --quiet --release --target-dir "$TARGET/compare-bevy-behave")
NEUROTREE="$TARGET/release/examples/chase"
BEVY_BEHAVE="$TARGET/compare-bevy-behave/release/bevy-behave-chase"

field() { # field NAME JSON
  sed -E "s/.*\"$1\":([0-9.]+).*/\1/" <<<"$2"
}

# Peak memory, when GNU time is there to tell it.
run() { # run BINARY N [ARGS...] -> JSON line, then "rss KB" on the next line if known
  local bin="$1" n="$2"
  shift 2
  if [ -x /usr/bin/time ]; then
    /usr/bin/time -f "rss %M" "$bin" --agents "$n" --frames "$FRAMES" --spacing "$SPACING" "$@" 2>"$TMP/err" | tail -1
    grep '^rss ' "$TMP/err" | tail -1
  else
    "$bin" --agents "$n" --frames "$FRAMES" --spacing "$SPACING" "$@" 2>/dev/null | tail -1
    echo "rss ?"
  fi
}

TMP="$(mktemp -d)"
trap 'rm -rf "$TMP"' EXIT

echo "machine: $(nproc) cores, $(uname -m); load average before: $(cut -d' ' -f1-3 /proc/loadavg); RAYON_NUM_THREADS=${RAYON_NUM_THREADS:-unset}"
echo "frames timed per run: $FRAMES; spacing: $SPACING"
echo
mb() { awk -v k="$1" 'BEGIN { if (k ~ /^[0-9]+$/) printf "%d", k / 1024; else printf "?" }'; }
ratio() { awk -v a="$1" -v b="$2" 'BEGIN { printf "%.2f", a / b }'; }
echo "ms/frame: the mean of the timed frames, then (after /) of their second half, once every tree"
echo "has started; bb/NT: bevy_behave's time over NeuroTree's (above 1: NeuroTree is faster)"
echo
printf '| %9s | %17s | %17s | %17s | %11s | %11s | %22s | %13s |\n' agents "bevy_behave" "NeuroTree" "NT, --lod" "bb/NT" "bb/NT lod" "chase frames bb/NT/lod" "RSS MB bb/NT"
printf '|%s|%s|%s|%s|%s|%s|%s|%s|\n' ----------: ------------------: ------------------: ------------------: ------------: ------------: -----------------------: --------------:
for n in $AGENTS; do
  out="$(run "$BEVY_BEHAVE" "$n")"
  bb="$(head -1 <<<"$out")"; bb_rss="$(tail -1 <<<"$out" | cut -d' ' -f2)"
  out="$(run "$NEUROTREE" "$n")"
  nt="$(head -1 <<<"$out")"; nt_rss="$(tail -1 <<<"$out" | cut -d' ' -f2)"
  out="$(run "$NEUROTREE" "$n" --lod)"
  lod="$(head -1 <<<"$out")"
  both() { echo "$(field ms_per_frame "$1") / $(field ms_steady "$1")"; }
  ratios() { echo "$(ratio "$(field ms_per_frame "$1")" "$(field ms_per_frame "$2")") / $(ratio "$(field ms_steady "$1")" "$(field ms_steady "$2")")"; }
  printf '| %9s | %17s | %17s | %17s | %11s | %11s | %22s | %13s |\n' "$n" "$(both "$bb")" "$(both "$nt")" "$(both "$lod")" \
    "$(ratios "$bb" "$nt")" "$(ratios "$bb" "$lod")" \
    "$(field chase "$bb") / $(field chase "$nt") / $(field chase "$lod")" "$(mb "$bb_rss") / $(mb "$nt_rss")"
done
echo
echo "load average after: $(cut -d' ' -f1-3 /proc/loadavg)"
