#!/bin/sh
# Takes the studio's pictures again, at 1500×950 in headless Chromium (and its ChromeDriver
# for those that need clicks), on the page as it is
# now: docs/images/studio-rewind-scene.png and studio-nav2-watch.png (`neurotree demo
# --studio`), studio-tree1111-folded.png (the editor on tree1111), and this folder's
# studio-edit.png, studio-watch.png and studio-replay.png; docs/images/studio-crowd-agent.png
# (one villager of the Bevy village example's `--studio`). Each but the rewind picture,
# tree1111's and the villager's is taken after "panels" and "fit" (fit_shot.py). Run from the
# repository root with Debian's `chromium` and `chromedriver`; it builds the `neurotree`
# binary and the example first.
set -eu
cargo build --quiet -p neurotree-cli
neurotree=${CARGO_TARGET_DIR:-target}/debug/neurotree
chromium=${CHROMIUM:-chromium}
images=docs/images
here=crates/neurotree-studio/docs
log=$(mktemp)
# tree1111's two conditions, declared for the editor.
model=$(mktemp --suffix=.xml)
cat > "$model" <<'XML'
<root BTCPP_format="4"><TreeNodesModel><Condition ID="Succ"/><Condition ID="Fail"/></TreeNodesModel></root>
XML
trap 'kill $server 2>/dev/null || true; rm -f "$log" "$model"' EXIT

# Starts `neurotree ARGS…` in the background and waits for the URL it prints.
serve() {
  : > "$log"
  "$neurotree" "$@" 2>"$log" >/dev/null &
  server=$!
  for _ in $(seq 100); do
    url=$(sed -n 's/^studio: \(http[^ ]*\).*/\1/p' "$log" | head -n 1)
    [ -n "$url" ] && return 0
    sleep 0.2
  done
  echo "the studio did not start: $(cat "$log")" >&2
  exit 1
}

stop() {
  kill "$server" 2>/dev/null || true
  wait "$server" 2>/dev/null || true
}

# shot URL FILE: the page at URL once it has had WAIT milliseconds to draw (default 6000).
shot() {
  "$chromium" --headless=new --no-sandbox --disable-gpu --hide-scrollbars \
    --window-size=1500,950 --virtual-time-budget="${WAIT:-6000}" \
    --screenshot="$2" "$1" 2>/dev/null
}

# fitshot URL VIEW FILE: the page at URL, its panels hidden and its tree fitted in VIEW.
fitshot() {
  python3 "$here/fit_shot.py" "$1" "$2" "$3" "${WAIT_SECONDS:-6}"
}

# The demo's navigator beside its warehouse, paused and taken eight ticks back (clicked
# through ChromeDriver), then the same run watched as it goes.
python3 "$here/rewind_shot.py" "$neurotree" "$images/studio-rewind-scene.png"
serve demo --studio 0 --speed 1 --max-ticks 100000
fitshot "${url}#view=watch" watch "$here/studio-watch.png"
stop

# One villager of the Bevy village example's thousand, watched.
cargo build --quiet -p neurotree-bevy --example village
: > "$log"
"${CARGO_TARGET_DIR:-target}/debug/examples/village" --studio 0 >"$log" 2>/dev/null &
server=$!
for _ in $(seq 100); do
  url=$(sed -n 's/^studio: \(http[^ ]*\).*/\1/p' "$log" | head -n 1)
  [ -n "$url" ] && break
  sleep 0.2
done
sleep 2
shot "$url" "$images/studio-crowd-agent.png"
stop

# The navigator alone, two ticks into a dry run, following its path (the run lingers).
nav2=corpus/nav2/navigate_to_pose_w_replanning_and_recovery.xml
serve run "$nav2" --nav2 --mock-unknown --mock FollowPath=RUNNING --set "goal=3;4;0" \
  --max-ticks 2 --studio 0 --studio-linger 60
fitshot "${url}#view=watch" watch "$images/studio-nav2-watch.png"
stop

# The editor on tree1111, folded to the depth that fits, and on Nav2's navigator.
serve studio --port 0 --model "$model" corpus/bench/tree1111.xml
shot "${url}#view=edit&file=corpus/bench/tree1111.xml" "$images/studio-tree1111-folded.png"
stop
serve studio --port 0 --nav2 "$nav2"
fitshot "${url}#view=edit&file=$nav2" edit "$here/studio-edit.png"
stop

# A replay of the navigator's dry run, at its last step (the trace inside the folder served).
trace=target/studio-replay.jsonl
mkdir -p target
"$neurotree" run "$nav2" --nav2 --mock-unknown --mock FollowPath=RUNNING --set "goal=3;4;0" \
  --max-ticks 3 --jsonl "$trace" >/dev/null || [ $? -eq 3 ]
serve studio --port 0 --nav2
fitshot "${url}#view=replay&file=$trace&tree=$nav2" replay "$here/studio-replay.png"
stop
rm -f "$trace"
