#!/usr/bin/env bash
# tree1111: NeuroTree beside BehaviorTree.CPP 4.10 built natively from its source with -O3,
# in one run. See README.md in this directory ("Native BehaviorTree.CPP").
#
# Usage: bash crates/neurotree-bench/compare/native.sh      (from any directory)
#
# It expects BehaviorTree.CPP's source (tag 4.10.0) in $BTCPP_SRC, by default in
# `btcpp-src` beside the repository (for /work/neurotree: /work/btcpp-src), e.g.
#   git clone --branch 4.10.0 --depth 1 https://github.com/BehaviorTree/BehaviorTree.CPP ../btcpp-src
# and needs cmake and a C++17 compiler. BehaviorTree.CPP is built as a static library
# without Groot2, SQLite, tools, examples or tests (so no ZeroMQ or SQLite), in Release with
# -O3; then btcpp_native/ is built against it.
# Environment:
#   BTCPP_SRC=dir      BehaviorTree.CPP's source (default: <repo>/../btcpp-src)
#   BTCPP_BUILD=dir    where to build both (default: $CARGO_TARGET_DIR or <repo>/target,
#                      then /btcpp-native)
#   ROUNDS=N           timed rounds of about 2 ms per measure and pass (default 100)
#   PASSES=N           how many times each program runs, in turn (default 5); the fastest
#                      round of all passes is kept, in both programs
set -euo pipefail

HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
REPO="$(cd "$HERE/../../.." && pwd)"
BTCPP_SRC="${BTCPP_SRC:-$REPO/../btcpp-src}"
TARGET="${CARGO_TARGET_DIR:-$REPO/target}"
BTCPP_BUILD="${BTCPP_BUILD:-$TARGET/btcpp-native}"
ROUNDS="${ROUNDS:-100}"
PASSES="${PASSES:-5}"
TREE="$REPO/corpus/bench/tree1111.xml"
JOBS="${JOBS:-$(nproc)}"

if [[ ! -f "$BTCPP_SRC/include/behaviortree_cpp/bt_factory.h" ]]; then
  echo "native.sh: no BehaviorTree.CPP source in $BTCPP_SRC (set BTCPP_SRC)" >&2
  exit 2
fi
BTCPP_SRC="$(cd "$BTCPP_SRC" && pwd)"
echo "BehaviorTree.CPP source: $BTCPP_SRC ($(grep -m1 -o "project(behaviortree_cpp VERSION [0-9.]*" "$BTCPP_SRC/CMakeLists.txt" | grep -o "[0-9.]*$"))"

# --- BehaviorTree.CPP, static, Release -O3 --------------------------------------------------
if [[ ! -f "$BTCPP_BUILD/lib/libbehaviortree_cpp.a" ]]; then
  cmake -S "$BTCPP_SRC" -B "$BTCPP_BUILD/lib" \
    -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_FLAGS_RELEASE="-O3 -DNDEBUG" \
    -DBTCPP_SHARED_LIBS=OFF -DBTCPP_GROOT_INTERFACE=OFF -DBTCPP_SQLITE_LOGGING=OFF \
    -DBTCPP_EXAMPLES=OFF -DBTCPP_BUILD_TOOLS=OFF -DBUILD_TESTING=OFF >/dev/null
  cmake --build "$BTCPP_BUILD/lib" -j "$JOBS"
fi

# --- the C++ benchmark ----------------------------------------------------------------------
cmake -S "$HERE/btcpp_native" -B "$BTCPP_BUILD/bench" -DCMAKE_BUILD_TYPE=Release \
  -DBTCPP_SRC="$BTCPP_SRC" -DBTCPP_BUILD_DIR="$BTCPP_BUILD/lib" >/dev/null
cmake --build "$BTCPP_BUILD/bench" -j "$JOBS" >/dev/null

# --- NeuroTree's equivalent -----------------------------------------------------------------
(cd "$REPO" && cargo build -q --profile bench -p neurotree-bench --example compare_native)
NT="$TARGET/release/examples/compare_native"

# --- one run: each in turn ------------------------------------------------------------------
echo "machine: $(nproc) cores, load average $(cut -d' ' -f1-3 /proc/loadavg), $(date -u +%FT%TZ)"
RESULTS="$(mktemp)"
trap 'rm -f "$RESULTS"' EXIT
# The two programs take turns, PASSES times each, so that both meet the same moments of a
# machine whose speed varies from second to second (a shared host's clock and neighbours):
# the fastest round of each measure over all passes is what the code costs.
for pass in $(seq "$PASSES"); do
  echo "pass $pass of $PASSES"
  "$BTCPP_BUILD/bench/btcpp_tree1111" "$TREE" "$ROUNDS" | tee -a "$RESULTS"
  "$NT" "$ROUNDS" | tee -a "$RESULTS"
done
echo "load average after: $(cut -d' ' -f1-3 /proc/loadavg)"

python3 - "$RESULTS" <<'PY'
import json, sys
r = {}
tick_times = []
for line in open(sys.argv[1]):
    line = line.strip()
    if line.startswith("{"):
        d = json.loads(line)
        if "p50_ns" in d:
            # Percentiles are kept pass by pass: a pass's tail is the moment it met.
            tick_times.append(d)
            continue
        # The fastest of the passes.
        key = "us_per_load" if "us_per_load" in d else "ns_per_node"
        if d["name"] not in r or d[key] < r[d["name"]][key]:
            r[d["name"]] = d
bt_tick = r["btcpp_native/tick"]["ns_per_node"]
bt_load = r["btcpp_native/load"]["us_per_load"]
print()
print(f"{'':34} {'ns/tick':>10} {'ns/node':>9} {'vs BT.CPP':>10}")
print(f"{'BehaviorTree.CPP 4.10 (native -O3)':34} {r['btcpp_native/tick']['ns_per_tick']:>10.1f} {bt_tick:>9.3f} {'1.0x':>10}")
b = r["btcpp_native/tick_builtin"]
print(f"{'  the same, built-in Always* leaves':34} {b['ns_per_tick']:>10.1f} {b['ns_per_node']:>9.3f}")
for name, label in [("neurotree/tick/builder", "NeuroTree, builder"),
                    ("neurotree/tick/xml", "NeuroTree, from XML")]:
    d = r[name]
    print(f"{label:34} {d['ns_per_tick']:>10.1f} {d['ns_per_node']:>9.3f} {bt_tick / d['ns_per_node']:>9.1f}x")
print()
print(f"{'load to instance (and drop)':34} {'us/load':>10} {'':>9} {'vs BT.CPP':>10}")
print(f"{'BehaviorTree.CPP 4.10 (native -O3)':34} {bt_load:>10.2f} {'':>9} {'1.0x':>10}")
nt_load = r["neurotree/load"]["us_per_load"]
print(f"{'NeuroTree':34} {nt_load:>10.2f} {'':>9} {bt_load / nt_load:>9.1f}x")
print()
print(f"{'tick times, each pass (ns)':34} {'p50':>8} {'p99':>8} {'p99.9':>8} {'max':>9}")
labels = {"btcpp_native/tick_times": "BehaviorTree.CPP 4.10", "neurotree/tick_times/xml": "NeuroTree, from XML"}
for d in tick_times:
    print(f"{labels.get(d['name'], d['name']):34} {d['p50_ns']:>8} {d['p99_ns']:>8} {d['p999_ns']:>8} {d['max_ns']:>9}")
PY
