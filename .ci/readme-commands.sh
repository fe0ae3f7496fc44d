#!/usr/bin/env bash
# Runs every shell command of the ```sh blocks of the README and of the guides (GUIDES below), as a newcomer
# would type them, in order, from the repository root. A line ending in `&` runs in the background until the next command ends. Commands CI runs in a
# step of its own, or that need what CI has not (a second terminal, a ground station), are listed as
# skipped with why. Fails at the first command that fails.
set -euo pipefail
cd "$(dirname "$0")/.."

skip_reason() {
  case "$1" in
    "cargo test"*) echo "CI's test step runs it" ;;
    ".ci/run"*) echo "this is CI" ;;
    "cargo bench"*) echo "criterion statistics take minutes; bench stn --json measures the same" ;;
    *"soak --missions 20 --seed 9000"*) echo "CI's soak step runs it" ;;
    *"goal send"*) echo "needs a companion listening for goals; .ci/interop/goals.sh uploads the same way" ;;
    *) echo "" ;;
  esac
}

# Each command of the ```sh blocks, continuation lines joined, comments dropped.
commands() {
  awk '
    /^```sh$/ { inblock = 1; next }
    /^```$/ { inblock = 0; next }
    inblock {
      line = $0
      sub(/[[:space:]]+#.*$/, "", line)
      if (line ~ /\\$/) { sub(/\\$/, "", line); acc = acc line; next }
      acc = acc line
      gsub(/[[:space:]]+/, " ", acc)
      if (acc != "" && acc != " ") print acc
      acc = ""
    }' "$1"
}

# The guides a newcomer follows command by command.
GUIDES=(docs/first-mission.md)

bg=""
# What the commands leave in the working tree (the first-mission guide's copy, report and pictures).
cleanup() { [ -n "$bg" ] && kill "$bg" 2>/dev/null || true; rm -rf my.ixt my-report.json my-report; }
trap cleanup EXIT

while IFS= read -r cmd; do
  why="$(skip_reason "$cmd")"
  if [ -n "$why" ]; then
    printf -- '-- skipped: %s  (%s)\n' "$cmd" "$why"
    continue
  fi
  if [[ "$cmd" == *"&" ]]; then
    printf -- '-- background: %s\n' "$cmd"
    bash -c "${cmd%&}" >/dev/null 2>&1 &
    bg=$!
    # The next command connects with retries (the link reconnects until --link-timeout).
    continue
  fi
  printf -- '-- run: %s\n' "$cmd"
  timeout 600 bash -c "$cmd" >/tmp/readme-command.out 2>&1 || {
    echo "FAILED: $cmd" >&2
    tail -30 /tmp/readme-command.out >&2
    exit 1
  }
  if [ -n "$bg" ]; then kill "$bg" 2>/dev/null || true; wait "$bg" 2>/dev/null || true; bg=""; fi
done < <(for f in README.md "${GUIDES[@]}"; do commands "$f"; done)
echo "README and guide commands: ok"
