#!/usr/bin/env bash
# Live page in a real browser (issue 18): headless Chromium from Debian's packages, driven by selenium (PyPI)
# through Debian's chromedriver (no browser download). An accelerated Fig. 2 demo serves its page on a free
# port; the browser checks that goals, actions and the resource plots appear and update, that a goal
# submitted through the form is accepted, and that one whose start window is over is rejected with its
# reason. Runs from the repository root; bounded polling with deadlines, no bare sleeps.
set -euo pipefail
cd "$(dirname "$0")/../.."

if ! command -v chromium >/dev/null || ! command -v chromedriver >/dev/null; then
  sudo=""
  [ "$(id -u)" = 0 ] || sudo="sudo"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends chromium chromium-driver >/dev/null
fi

target="${CARGO_TARGET_DIR:-target}"
venv="$target/browser-venv"
if [ ! -x "$venv/bin/python" ] || ! "$venv/bin/python" -c 'import selenium' 2>/dev/null; then
  python3 -m venv "$venv"
  "$venv/bin/pip" install --quiet --upgrade pip
  "$venv/bin/pip" install --quiet selenium
fi

cargo build --release --quiet --bin mavtempo
work="$(mktemp -d)"
demo_pid=""
cleanup() {
  if [ -n "$demo_pid" ]; then kill "$demo_pid" 2>/dev/null || true; fi
  rm -rf "$work"
}
trap cleanup EXIT

"$target/release/mavtempo" demo --quiet --speedup 10 --no-upload --http 127.0.0.1:0 --http-goals \
  > "$work/demo.out" 2> "$work/demo.err" &
demo_pid=$!
for _ in $(seq 1 300); do
  grep -q '^http listening on ' "$work/demo.out" 2>/dev/null && break
  kill -0 "$demo_pid" 2>/dev/null || break
  sleep 0.1
done
url="$(sed -n 's/^http listening on //p' "$work/demo.out")"
[ -n "$url" ] || { echo "the demo did not serve its page" >&2; cat "$work/demo.out" "$work/demo.err" >&2; exit 1; }
echo "live page at $url"

timeout 150 "$venv/bin/python" .ci/interop/browser_page.py "$url"
