#!/usr/bin/env python3
"""mavtempo alone on every domain of the development set (../shared/benchmarks: IPC-2002 and IPC-2008
temporal domains), p1..pN each, `mavtempo plan` per instance with a wall-clock limit (issue 32).

Each answer is classified: `solved` (a plan, accepted by the checker and replayed on the PDDL), `no-plan`
(the planner declared the problem infeasible: search exhausted, no resolver, unreachable goal), `refused`
(the reader or the translation refused the file, with its located reason), `timeout` (the limit ran out),
`error` (anything else). A `no-plan` where a peer finds a plan is a bug: the table lists them first.

Usage: devset.py [--mavtempo BIN] [--dir DIR] [--instances 1-10] [--time-limit 10] [--domains a,b]
                 [--out FILE.jsonl] [--plans-out DIR]
       devset.py --report --out FILE.jsonl        (the table again, from saved results)
Output: one JSON line per instance in --out (folder, instance, outcome, secs, actions, reason); a Markdown
table per domain on standard output (solved / instances, median time of the solved, the other outcomes).
"""

import argparse
import json
import statistics
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
NO_PLAN = ("search exhausted", "no resolver for the root flaw", "cannot be achieved", "has no plan")


def folders(root, wanted):
    """Every benchmark folder under root (those holding `instances/`), sorted; filtered by substrings."""
    out = sorted(p for p in Path(root).glob("*/*") if (p / "instances").is_dir())
    if wanted:
        out = [p for p in out if any(w in p.name for w in wanted)]
    return out


def domain_file(folder, n):
    own = folder / "domains" / f"domain-{n}.pddl"
    return own if own.is_file() else folder / "domain.pddl"


def classify(rc, text):
    """The outcome of one `mavtempo plan` run from its exit code and output."""
    if rc == 0 and "IPC plan replayed on the PDDL: valid" in text:
        return "solved"
    if any(k in text for k in NO_PLAN):
        return "no-plan"
    if "deadline reached" in text:
        return "timeout"
    if "error:" in text:
        return "refused"
    return "error"


def run_one(binary, folder, n, limit, plans_out):
    dom, prob = domain_file(folder, n), folder / "instances" / f"instance-{n}.pddl"
    cmd = [binary, "plan", str(dom), str(prob), "--max-steps", "1000000000"]
    if plans_out:
        plan_dir = Path(plans_out) / folder.name
        plan_dir.mkdir(parents=True, exist_ok=True)
        cmd += ["--pddl-out", str(plan_dir / f"instance-{n}.plan")]
    t0 = time.monotonic()
    try:
        p = subprocess.run(cmd, capture_output=True, text=True, timeout=limit)
        rc, text = p.returncode, p.stdout + p.stderr
    except subprocess.TimeoutExpired:
        rc, text = None, "deadline reached (killed at the time limit)"
    secs = time.monotonic() - t0
    outcome = classify(rc, text)
    actions = None
    reason = None
    for line in text.splitlines():
        if " actions, makespan " in line:
            actions = int(line.split()[0])
        if outcome != "solved" and ("error" in line or "no plan" in line or "deadline" in line):
            reason = line.strip()[:300]
    return {"folder": folder.name, "set": folder.parent.name, "instance": n, "outcome": outcome,
            "secs": round(secs, 3), "actions": actions, "reason": reason}


def report(rows):
    by = {}
    for r in rows:
        by.setdefault(r["folder"], []).append(r)
    print("| domain | solved | median s (solved) | no plan | refused | timeout | error |")
    print("|---|---|---|---|---|---|---|")
    total = solved_all = 0
    for folder in sorted(by):
        rs = by[folder]
        count = lambda o: sum(r["outcome"] == o for r in rs)
        times = [r["secs"] for r in rs if r["outcome"] == "solved"]
        med = f"{statistics.median(times):.2f}" if times else "–"
        total += len(rs)
        solved_all += len(times)
        print(f"| {folder} | {len(times)}/{len(rs)} | {med} | {count('no-plan')} | {count('refused')} "
              f"| {count('timeout')} | {count('error')} |")
    print(f"| **all** | {solved_all}/{total} | | | | | |")
    bad = [r for r in rows if r["outcome"] == "no-plan"]
    if bad:
        print("\nDeclared infeasible:")
        for r in bad:
            print(f"- {r['folder']} p{r['instance']}: {r['reason']}")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--mavtempo", default=str(ROOT / "target/release/mavtempo"))
    # ../shared/benchmarks beside the checkout (a worktree under wt/ looks one level further up).
    near = [d / "shared/benchmarks" for d in (ROOT.parent, ROOT.parent.parent)]
    ap.add_argument("--dir", default=str(next((d for d in near if d.is_dir()), near[0])))
    ap.add_argument("--instances", default="1-10")
    ap.add_argument("--time-limit", type=float, default=10.0)
    ap.add_argument("--domains", default="")
    ap.add_argument("--out", default="target/devset.jsonl")
    ap.add_argument("--plans-out", default="")
    ap.add_argument("--report", action="store_true")
    a = ap.parse_args()
    if a.report:
        report([json.loads(l) for l in Path(a.out).read_text().splitlines() if l.strip()])
        return 0
    lo, _, hi = a.instances.partition("-")
    instances = range(int(lo), int(hi or lo) + 1)
    wanted = [w for w in a.domains.split(",") if w]
    chosen = folders(a.dir, wanted)
    if not chosen:
        print(f"devset.py: no benchmark folder under {a.dir}", file=sys.stderr)
        return 1
    rows = []
    Path(a.out).parent.mkdir(parents=True, exist_ok=True)
    with open(a.out, "w") as f:
        for folder in chosen:
            for n in instances:
                if not (folder / "instances" / f"instance-{n}.pddl").is_file():
                    continue
                r = run_one(a.mavtempo, folder, n, a.time_limit, a.plans_out)
                rows.append(r)
                f.write(json.dumps(r) + "\n")
                f.flush()
                print(f"{r['folder']} p{n}: {r['outcome']} {r['secs']} s", file=sys.stderr)
    report(rows)
    return 0


if __name__ == "__main__":
    sys.exit(main())
