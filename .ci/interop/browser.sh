#!/usr/bin/env bash
# Live page in a real browser (issue 18): headless Chromium from Debian's packages, driven by selenium (PyPI)
# through Debian's chromedriver (no browser download). An accelerated Fig. 2 demo serves its page on a free
# port; the browser checks that goals, actions and the resource plots appear and update, that a goal
# submitted through the form is accepted (the table says so, with the station it came from) and that its
# cancel button withdraws it (`cancelled`), that the vehicle's mode shows, and that a goal whose start
# window is over is rejected with its reason. Runs from the repository root; bounded polling with deadlines, no bare sleeps.
set -euo pipefail
cd "$(dirname "$0")/../.."
. .ci/interop/lib/common.sh

if ! command -v chromium >/dev/null || ! command -v chromedriver >/dev/null; then
  sudo=""
  [ "$(id -u)" = 0 ] || sudo="sudo"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends chromium chromium-driver >/dev/null
fi

target="${CARGO_TARGET_DIR:-target}"
venv="$target/browser-venv"
ensure_venv "$venv" selenium selenium

cargo build --release --quiet --bin mavtempo
scratch_dir

"$target/release/mavtempo" demo --quiet --speedup 10 --no-upload --http 127.0.0.1:0 --http-goals \
  > "$work/demo.out" 2> "$work/demo.err" &
bg_pid=$!
wait_for_line "$work/demo.out" '^http listening on ' "$bg_pid" \
  || { echo "the demo did not serve its page" >&2; cat "$work/demo.out" "$work/demo.err" >&2; exit 1; }
url="$(sed -n 's/^http listening on //p' "$work/demo.out")"
echo "live page at $url"

timeout 150 "$venv/bin/python" .ci/interop/browser_page.py "$url"
