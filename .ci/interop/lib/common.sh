# Sourced by the interop scripts (.ci/interop/*.sh; this folder is not run by .ci/run): what they all do.
# Each script stays runnable on its own from any directory.

# ensure_venv VENV MODULES PACKAGE...: a virtualenv at VENV where `import MODULES` works, PACKAGEs
# installed from PyPI when it does not. PYTHON: the interpreter to create it with (python3).
ensure_venv() {
  local venv="$1" modules="$2"
  shift 2
  if [ ! -x "$venv/bin/python" ] || ! "$venv/bin/python" -c "import $modules" 2>/dev/null; then
    "${PYTHON:-python3}" -m venv "$venv"
    "$venv/bin/pip" install --quiet --upgrade pip
    "$venv/bin/pip" install --quiet "$@"
  fi
}

# scratch_dir: a directory in $work, removed on exit together with the background process whose pid is
# in $bg_pid (set it after starting one; empty: none).
scratch_dir() {
  work="$(mktemp -d)"
  bg_pid=""
  trap scratch_cleanup EXIT
}

scratch_cleanup() {
  if [ -n "$bg_pid" ]; then kill "$bg_pid" 2>/dev/null || true; fi
  rm -rf "$work"
}

# wait_for_line FILE PATTERN PID: polls FILE every 0.1 s, for 30 s at most, until a line matches the grep
# PATTERN; gives up early when process PID has ended. Fails when no line came.
wait_for_line() {
  local file="$1" pattern="$2" pid="$3"
  for _ in $(seq 1 300); do
    grep -q "$pattern" "$file" 2>/dev/null && return 0
    kill -0 "$pid" 2>/dev/null || break
    sleep 0.1
  done
  grep -q "$pattern" "$file" 2>/dev/null
}
