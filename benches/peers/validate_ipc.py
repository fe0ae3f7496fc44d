#!/usr/bin/env python3
"""mavtempo's IPC-2002 plans checked by an independent validator (issue 17; run in CI by .ci/interop/pddl.sh).

Reads the plans `mavtempo bench ipc --plans-out DIR` wrote (DIR/<folder>/instance-N.plan) and, when given, the
bench's --json lines (why an instance was not solved), and checks every plan with unified-planning's temporal plan
validator. Fails (exit 1, each instance with the reason) when an instance of a --required variant is unsolved,
its plan rejected or not checkable. Other variants (Time, numeric) are checked where unified-planning can read
them, and their share solved and validated is printed.

--corrupt DOMAIN:VARIANT:N proves the check can fail: that plan's last step that needs what earlier steps
achieve (a Rovers communicate_*, a Satellite take_image) is moved to time 0, and the copy without its last step
is tried too; the validator must reject both (exit 1 when it accepts one).

Usage: validate_ipc.py --plans DIR [--bench-jsonl FILE] [--dir IPC2002] [--domains rovers,satellite]
                       [--variants simple,time] [--instances 1-10] [--required simple] [--corrupt rovers:simple:1]
"""

import argparse
import sys
from pathlib import Path

import ipcbench
import peerslib

ROOT = Path(__file__).resolve().parents[2]
# The steps that need what the plan achieved before them: none of them can start at 0.
NEEDS_EARLIER_STEPS = {"rovers": "communicate_", "satellite": "take_image"}


def bench_lines(path):
    """(domain, variant, instance) -> that `bench ipc --json` line."""
    if path is None:
        return {}
    return {(j.get("domain"), j.get("variant"), j.get("instance")): j for j in peerslib.read_jsonl(path)}


def verdict(b, plans_dir, line):
    """(solved, valid, reason) of one benchmark: valid None when unified-planning could not check the plan."""
    if line is not None and not line.get("solved"):
        return False, None, f"not solved: {line.get('reason') or 'no reason given'}"
    path = ipcbench.plan_path(plans_dir, b)
    if not path.is_file():
        return False, None, f"no plan file {path}"
    res = ipcbench.check_plan_file(b, path, read_cached(b))
    return True, res["valid"], res["error"]


_PROBLEMS = {}


def read_cached(b):
    """unified-planning's reading of a benchmark, or None when it cannot read it (check_plan then says why)."""
    if b not in _PROBLEMS:
        try:
            _PROBLEMS[b] = peerslib.read_problem(b.domain_file, b.problem_file)
        except Exception:
            _PROBLEMS[b] = None
    return _PROBLEMS[b]


def check_all(benches, plans_dir, lines, required, min_validated=None):
    """Prints one line per benchmark and a share per (domain, variant); returns the failures: a plan the
    validator rejected (any variant), and a required instance not validated — or, with `min_validated`, fewer
    validated required instances than that (a regression floor while some are known to be unsolved)."""
    failures, shares, validated_required = [], {}, 0
    for b in benches:
        solved, valid, reason = verdict(b, plans_dir, lines.get((b.domain, b.variant, b.instance)))
        state = "valid" if valid else "REJECTED" if valid is False else "solved, not checked" if solved else "UNSOLVED"
        print(f"{ipcbench.label(b)}: {state}" + (f" ({one_line(reason, 300)})" if reason else ""))
        share = shares.setdefault((b.domain, b.variant), {"n": 0, "solved": 0, "valid": 0, "why": set()})
        share["n"] += 1
        share["solved"] += solved
        share["valid"] += valid is True
        if valid is not True and reason:
            share["why"].add(f"{state.lower()}: {one_line(reason, 160)}")
        if valid is False and b.variant not in required:
            failures.append(f"{ipcbench.label(b)}: {state}: {reason}")
        if b.variant in required:
            validated_required += valid is True
            if valid is False or (valid is not True and min_validated is None):
                failures.append(f"{ipcbench.label(b)}: {state}: {reason}")
    if min_validated is not None and validated_required < min_validated:
        failures.append(f"{validated_required} required instances validated, fewer than the floor {min_validated}")
    for (dom, var), share in shares.items():
        print(f"== {dom} {var}: solved {share['solved']}/{share['n']}, validated {share['valid']}/{share['n']}"
              + "".join(f"\n   {why}" for why in sorted(share["why"])))
    return failures


def one_line(text, width):
    return " ".join(str(text).split())[:width]


def corrupted(text, domain):
    """Two broken copies of a plan text: the last step that needs earlier steps moved to 0.000, and the plan
    without its last step (goals left unachieved). ValueError when the plan has no such step."""
    lines = text.splitlines()
    steps = [(i, parsed[0]) for i, parsed in enumerate(peerslib.ipc_steps(line) for line in lines) if parsed]
    late = [(i, s) for i, s in steps if s[1].startswith(NEEDS_EARLIER_STEPS[domain]) and s[0] > 0]
    if not late:
        raise ValueError(f"no {NEEDS_EARLIER_STEPS[domain]} step after time 0 to move")
    i, (start, name, args, dur) = max(late, key=lambda t: t[1][0])
    moved = list(lines)
    moved[i] = f"0.000: ({' '.join([name] + args)}) [{float(dur):.3f}]"
    last = max(steps, key=lambda t: t[1][0])[0]
    truncated = [line for k, line in enumerate(lines) if k != last]
    return {f"({name} ...) moved from {float(start):.3f} to 0.000": "\n".join(moved) + "\n",
            "its last step removed": "\n".join(truncated) + "\n"}


def corruption_check(spec, root, plans_dir):
    """The negative check: every broken copy of that plan must be rejected. Returns the failures."""
    dom, var, n = spec.split(":")
    b = ipcbench.benchmarks(root, [dom], [var], [int(n)])[0]
    path = ipcbench.plan_path(plans_dir, b)
    try:
        copies = corrupted(path.read_text(), dom)
    except (OSError, ValueError) as e:
        return [f"negative check on {ipcbench.label(b)}: cannot corrupt {path}: {e}"]
    failures = []
    for what, text in copies.items():
        res = ipcbench.check_plan(b, text, read_cached(b))
        ok = res["valid"] is False
        print(f"negative check, {ipcbench.label(b)} with {what}: "
              + (f"rejected as it must be ({res['error']})" if ok else f"NOT rejected ({res['error'] or 'valid'})"))
        if not ok:
            failures.append(f"negative check: {ipcbench.label(b)} with {what} was not rejected")
    return failures


def parse_args():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--plans", required=True, help="the --plans-out DIR of `mavtempo bench ipc`")
    ap.add_argument("--bench-jsonl", help="the --json output of that bench run")
    ap.add_argument("--dir", default=str(ROOT / ".." / "shared" / "benchmarks" / "ipc2002"))
    ap.add_argument("--domains", default=",".join(ipcbench.DOMAINS))
    ap.add_argument("--variants", default=",".join(ipcbench.VARIANTS))
    ap.add_argument("--instances", default="1-10")
    ap.add_argument("--required", default="simple", help="variants whose every instance must be validated")
    ap.add_argument("--min-validated", type=int,
                    help="instead of every required instance: at least this many validated (rejections still fail)")
    ap.add_argument("--corrupt", help="DOMAIN:VARIANT:N, the plan whose broken copies must be rejected")
    return ap.parse_args()


def main():
    args = parse_args()
    try:
        variants = ipcbench.names(args.variants, list(ipcbench.VARIANTS), "variant")
        benches = ipcbench.benchmarks(args.dir, ipcbench.names(args.domains, ipcbench.DOMAINS, "domain"),
                                      variants, ipcbench.instance_range(args.instances))
        required = ipcbench.names(args.required, list(ipcbench.VARIANTS), "variant")
        failures = check_all(benches, args.plans, bench_lines(args.bench_jsonl), required, args.min_validated)
        if args.corrupt:
            failures += corruption_check(args.corrupt, args.dir, args.plans)
    except (OSError, ValueError, KeyError) as e:
        sys.exit(f"validate_ipc.py: {e}")
    if failures:
        print(f"\nFAILED ({len(failures)}):\n" + "\n".join(failures), file=sys.stderr)
        sys.exit(1)
    print("all required plans validated; the broken copies rejected" if args.corrupt
          else "all required plans validated")


if __name__ == "__main__":
    main()
