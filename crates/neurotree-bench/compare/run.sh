#!/usr/bin/env bash
# Side-by-side tree1111 benchmark: NeuroTree vs BehaviorTree.CPP 4
# (behaviortreepy), py_trees and bonsai-bt. See README.md in this directory.
#
# Usage: bash crates/neurotree-bench/compare/run.sh            (from any directory)
# Environment:
#   TREE1111=path      tree to use (absolute, relative to the current directory,
#                      or relative to the repository root);
#                      default: <repo>/corpus/bench/tree1111.xml
#   BTCPP_TICKS=N      timed ticks for BehaviorTree.CPP   (default 5000)
#   PYTREES_TICKS=N    timed ticks for py_trees           (default 200)
#   BONSAI_TICKS=N     timed ticks for bonsai-bt          (default 20000)
set -euo pipefail

HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
REPO="$(cd "$HERE/../../.." && pwd)"

# Versions this benchmark was written and checked against.
BEHAVIORTREEPY_VERSION="0.1.4"   # bundles BehaviorTree.CPP 4
PYTREES_VERSION="2.6.0"

# --- locate the tree ---------------------------------------------------------
resolve_tree() {
  local p="$1"
  if [[ "$p" = /* ]]; then
    [[ -f "$p" ]] && { echo "$p"; return 0; }
  else
    [[ -f "$p" ]] && { echo "$(cd "$(dirname "$p")" && pwd)/$(basename "$p")"; return 0; }
    [[ -f "$REPO/$p" ]] && { echo "$(cd "$(dirname "$REPO/$p")" && pwd)/$(basename "$p")"; return 0; }
  fi
  return 1
}
TREE_ARG="${TREE1111:-corpus/bench/tree1111.xml}"
if ! TREE="$(resolve_tree "$TREE_ARG")"; then
  echo "run.sh: tree not found: $TREE_ARG (looked in $PWD and $REPO)" >&2
  exit 2
fi
export TREE1111="$TREE"
echo "tree: $TREE"

RESULTS="$(mktemp)"
trap 'rm -f "$RESULTS"' EXIT
FAILED=0

# Keep the first JSON line of stdin that has "name":"<wanted>" (or any name if
# no name is given) and append it to $RESULTS. Reads all of stdin so the
# producer never gets SIGPIPE.
collect() {
  local wanted="${1:-}" line found=""
  while IFS= read -r line; do
    [[ -z "$found" && "$line" == \{*\"name\"* ]] || continue
    if [[ -z "$wanted" || "$line" == *"\"name\":\"$wanted\""* ]]; then
      found="$line"
      echo "$line" >>"$RESULTS"
      echo "  $line"
    fi
  done
  [[ -n "$found" ]]
}

# --- Python environment ------------------------------------------------------
VENV="$HERE/.venv"
PY="$VENV/bin/python"
if ! "$PY" -c 'import sys' >/dev/null 2>&1; then
  echo "creating $VENV"
  rm -rf "$VENV"
  python3 -m venv "$VENV"
fi
if ! "$PY" - "$BEHAVIORTREEPY_VERSION" "$PYTREES_VERSION" >/dev/null 2>&1 <<'EOF'
import sys, importlib.metadata as m
assert m.version("behaviortreepy") == sys.argv[1]
assert m.version("py_trees") == sys.argv[2]
EOF
then
  echo "installing behaviortreepy==$BEHAVIORTREEPY_VERSION py-trees==$PYTREES_VERSION"
  PIP_DISABLE_PIP_VERSION_CHECK=1 "$PY" -m pip install -q \
    "behaviortreepy==$BEHAVIORTREEPY_VERSION" "py-trees==$PYTREES_VERSION"
fi

# --- runners -----------------------------------------------------------------
echo "== BehaviorTree.CPP 4 (behaviortreepy $BEHAVIORTREEPY_VERSION)"
if ! "$PY" "$HERE/btcpp_tree1111.py" "$TREE" --ticks "${BTCPP_TICKS:-5000}" | collect btcpp; then
  echo "btcpp: FAILED"; FAILED=1
fi

echo "== py_trees $PYTREES_VERSION"
if ! "$PY" "$HERE/pytrees_tree1111.py" "$TREE" --ticks "${PYTREES_TICKS:-200}" | collect py_trees; then
  echo "py_trees: FAILED"; FAILED=1
fi

echo "== bonsai-bt (building crates/neurotree-bench/compare/bonsai)"
if ! cargo build --release -q --manifest-path "$HERE/bonsai/Cargo.toml"; then
  echo "bonsai-bt: build FAILED"; FAILED=1
elif ! cargo run --release -q --manifest-path "$HERE/bonsai/Cargo.toml" -- \
       "$TREE" "${BONSAI_TICKS:-20000}" | collect bonsai-bt; then
  echo "bonsai-bt: FAILED"; FAILED=1
fi

echo "== NeuroTree"
NT_ERR="$(mktemp)"
if ! (cd "$REPO" && cargo run --profile dist -q -p neurotree-cli -- bench --json 2>"$NT_ERR") \
     | collect tree1111; then
  echo "neurotree: not available"
  tail -n 5 "$NT_ERR" | sed 's/^/  | /'
fi
rm -f "$NT_ERR"

# --- table -------------------------------------------------------------------
echo
"$PY" - "$RESULTS" <<'EOF'
import json, sys

rows = [json.loads(l) for l in open(sys.argv[1]) if l.strip()]
labels = {
    "tree1111": "NeuroTree",
    "btcpp": "BehaviorTree.CPP 4 (behaviortreepy)",
    "py_trees": "py_trees",
    "bonsai-bt": "bonsai-bt",
}
order = ["tree1111", "btcpp", "bonsai-bt", "py_trees"]
rows.sort(key=lambda r: order.index(r["name"]) if r["name"] in order else len(order))
base = next((r for r in rows if r["name"] == "tree1111"), None)

head = ("implementation", "ns/tick", "ns/node", "vs NeuroTree")
table = []
for r in rows:
    ratio = "n/a" if base is None else f'{r["ns_per_node"] / base["ns_per_node"]:.2f}x'
    table.append((labels.get(r["name"], r["name"]), f'{r["ns_per_tick"]:,.0f}',
                  f'{r["ns_per_node"]:,.2f}', ratio))
w = [max(len(x[i]) for x in [head] + table) for i in range(4)]
fmt = lambda x: f"{x[0]:<{w[0]}}  {x[1]:>{w[1]}}  {x[2]:>{w[2]}}  {x[3]:>{w[3]}}"
print(fmt(head))
print("  ".join("-" * n for n in w))
for x in table:
    print(fmt(x))
print(f'\n{rows[0]["nodes_per_tick"] if rows else 1111} nodes visited per tick; '
      '"vs NeuroTree" = ns/node divided by NeuroTree\'s ns/node (higher = slower).')
EOF

exit "$FAILED"
