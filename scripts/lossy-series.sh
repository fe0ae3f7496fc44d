#!/usr/bin/env bash
# Fig. 2 over a lossy radio: for each loss level, one `mavtempo demo` run per seed on
# sitl/scenarios/fig2.toml plus a link_quality fault from t = 0 (loss L, duplication and reordering as
# given, both directions), then a table: per run the goals achieved and whether every goal the clean run
# achieved is among them.
#
#   scripts/lossy-series.sh [-l "0 0.2 0.4"] [-s "101 102 ... 110"] [-d 0.05] [-r 0.05] [-x 20] [-u] [-o DIR]
#     -l  loss levels            -s  seeds (the SITL's: link faults and picture sizes)
#     -d  duplication            -r  reordering
#     -x  speed-up (paced at N×; "step" for the stepped, deterministic clock)
#     -u  with the ground station's g6/g7 upload (default: --no-upload)
#     -o  where scenarios and JSON reports go (default: a temporary directory)
#     -f  a TOML file of more [[faults]] added to every run's scenario (e.g. a reboot)
# Needs a release build (cargo build --release; MAVTEMPO_BIN=path overrides it) and jq. Exit 1 if a run fails to end.
set -euo pipefail

levels="0 0.2 0.4"
seeds="101 102 103 104 105 106 107 108 109 110"
dup=0.05
reorder=0.05
speedup=20
upload=--no-upload
out=""
more_faults=/dev/null
while getopts "l:s:d:r:x:uo:f:" opt; do
  case $opt in
    l) levels=$OPTARG ;;
    s) seeds=$OPTARG ;;
    d) dup=$OPTARG ;;
    r) reorder=$OPTARG ;;
    x) speedup=$OPTARG ;;
    u) upload="" ;;
    o) out=$OPTARG ;;
    f) more_faults=$OPTARG ;;
    *) sed -n 2,14p "$0"; exit 2 ;;
  esac
done
root=$(cd "$(dirname "$0")/.." && pwd)
bin=${MAVTEMPO_BIN:-${CARGO_TARGET_DIR:-$root/target}/release/mavtempo}
[ -x "$bin" ] || { echo "no $bin: cargo build --release first" >&2; exit 2; }
out=${out:-$(mktemp -d)}
mkdir -p "$out"
pace=()
[ "$speedup" = step ] || pace=(--speedup "$speedup")

# The clean run's achieved goals (seed 1, no link fault): the reference.
goals_of() { jq -r '[.goals[] | select(.fate == "achieved") | .name] | join(",")' "$1"; }
(cd "$root" && "$bin" demo --quiet $upload "${pace[@]}" --report "$out/clean.json" >/dev/null)
clean=$(goals_of "$out/clean.json")
echo "clean run: achieved $clean ($(jq -r .end "$out/clean.json"))"
echo
echo "| loss | dup | reorder | seed | end | mission s | achieved | rejected (reason) | replans | clean run's goals kept |"
echo "|---|---|---|---|---|---|---|---|---|---|"
status=0
for l in $levels; do
  scen="$out/fig2-loss$l.toml"
  { cat "$root/sitl/scenarios/fig2.toml"
    printf '\n[[faults]]\nwhen = { at_s = 0.0 }\n'
    printf 'fault = { kind = "link_quality", loss = %s, duplicate = %s, reorder = %s }\n' "$l" "$dup" "$reorder"
    cat "$more_faults"
  } >"$scen"
  same=0; n=0
  for s in $seeds; do
    rep="$out/loss$l-seed$s.json"
    if ! (cd "$root" && timeout 900 "$bin" demo --quiet $upload "${pace[@]}" --seed "$s" \
          --scenario "$scen" --report "$rep" >"$out/loss$l-seed$s.log" 2>&1); then
      echo "| $l | $dup | $reorder | $s | FAILED (see $out/loss$l-seed$s.log) | | | | | no |"
      status=1; n=$((n + 1)); continue
    fi
    got=$(goals_of "$rep")
    rej=$(jq -r '[.goals[] | select(.fate != "achieved") | "\(.name) \(.fate): \(.reason)"] | join("; ")' "$rep")
    # Every goal of the clean run achieved (more is noted: a lossy run may also make a window the clean missed).
    missing=$(comm -23 <(tr , '\n' <<<"$clean" | sort) <(tr , '\n' <<<"$got" | sort) | paste -sd, -)
    extra=$(comm -13 <(tr , '\n' <<<"$clean" | sort) <(tr , '\n' <<<"$got" | sort) | paste -sd, -)
    if [ -z "$missing" ]; then
      ok=yes; same=$((same + 1)); [ -n "$extra" ] && ok="yes (+$extra)"
    else
      ok="no (-$missing)"
    fi
    n=$((n + 1))
    printf '| %s | %s | %s | %s | %s | %.1f | %s | %s | %s | %s |\n' "$l" "$dup" "$reorder" "$s" \
      "$(jq -r .end "$rep")" "$(jq -r '.duration_ms / 1000' "$rep")" "${got:--}" "${rej:--}" \
      "$(jq -r .counters.replans "$rep")" "$ok"
  done
  echo "loss $l: $same of $n runs achieved every goal of the clean run" >&2
done
echo "reports in $out" >&2
exit $status
