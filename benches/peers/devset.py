#!/usr/bin/env python3
"""mavtempo beside LPG-td and Kairos on every domain of the development set (../shared/benchmarks: IPC-2002 and
IPC-2008 temporal domains), p1..pN each, the same wall-clock limit, one run at a time, every plan checked by
unified-planning's validator (issue 32).

mavtempo runs as `mavtempo plan` per instance; its answer is classified `solved` (a plan, accepted by its checker
and replayed on the PDDL), `no-plan` (declared infeasible: search exhausted, no resolver, unreachable goal),
`refused` (the reader or the translation refused the file, with its located reason), `timeout`, `error`. The
peers run through benches/peers/peerslib.py (LPG-td on its own command line, Kairos through unified-planning);
their answers are `solved`, `unsolved` (gave up before the limit), `timeout`, `error`. Every plan, mavtempo's
too, is then given to unified-planning's validator: `valid` True, False (a rejected plan is not solved) or None
with the reason in `check` (unified-planning cannot read that domain: the plan counts as solved, marked
"n.v." in the table, never silently). A mavtempo `no-plan` where a peer finds a plan is a bug: listed first.

Usage: devset.py [--planners mavtempo,lpg,kairos] [--mavtempo BIN] [--dir DIR] [--instances 1-10]
                 [--time-limit 10] [--domains a,b] [--out FILE.jsonl] [--plans-out DIR] [--merge FILE ...]
       devset.py --report --out FILE.jsonl [--merge FILE ...]   (the table again, from saved results)
--merge adds the rows of saved runs (e.g. the peers' of an earlier run) for the planners not run now.
Without unified-planning importable (the peers' virtualenv, benches/peers/devset.sh) mavtempo runs alone
and its plans are left unchecked. Output: one JSON line per (instance, planner) in --out (folder, set,
instance, planner, outcome, secs, makespan, actions, valid, check, reason); the Markdown table on standard
output: per domain and planner solved / instances (median time, median makespan of the solved), the median
times of mavtempo and LPG-td on the instances both solve, and mavtempo's other outcomes.
"""

import argparse
import importlib.util
import json
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import peerslib

ROOT = Path(__file__).resolve().parents[2]
NO_PLAN = ("search exhausted", "no resolver for the root flaw", "cannot be achieved", "has no plan")
PLANNERS = ["mavtempo", "lpg", "kairos"]
TITLES = {"mavtempo": "mavtempo", "lpg": "LPG-td", "kairos": "Kairos", "aries": "Aries"}
# unified-planning's validator on a large plan may take long: its own limit.
CHECK_LIMIT = 60.0


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


def run_mavtempo(binary, dom, prob, limit):
    """(row fields, IPC plan text or None) of one `mavtempo plan` run."""
    with tempfile.TemporaryDirectory() as tmp:
        plan_file = Path(tmp) / "plan"
        cmd = [binary, "plan", str(dom), str(prob), "--max-steps", "1000000000", "--pddl-out", str(plan_file)]
        t0 = time.monotonic()
        try:
            p = subprocess.run(cmd, capture_output=True, text=True, timeout=limit)
            rc, text = p.returncode, p.stdout + p.stderr
        except subprocess.TimeoutExpired:
            rc, text = None, "deadline reached (killed at the time limit)"
        secs = time.monotonic() - t0
        plan = plan_file.read_text() if plan_file.is_file() else None
    outcome = classify(rc, text)
    reason = None
    if outcome != "solved":
        plan = None
        for line in text.splitlines():
            if "error" in line or "no plan" in line or "deadline" in line:
                reason = line.strip()[:300]
    return {"outcome": outcome, "secs": round(secs, 3), "reason": reason}, plan


def run_peer(planner, dom, prob, limit):
    """(row fields, IPC plan text or None) of one peer run, validated in its child process."""
    r = peerslib.run_one(planner, dom, prob, limit)
    status, ms = r["status"], r["ms"]
    if status in peerslib.SOLVED and ms is not None and ms <= limit * 1e3:
        outcome = "solved"
    elif status in ("TIMEOUT", "KILLED") or status in peerslib.SOLVED or (ms or 0) >= limit * 1e3:
        outcome = "timeout"
    elif status == "ERROR" or status == "CRASHED":
        outcome = "error"
    else:
        outcome = "unsolved"
    row = {"outcome": outcome, "secs": round((ms or 0) / 1e3, 3), "reason": r["error"] if outcome != "solved"
           else None, "valid": r["valid"], "check": r["error"] if r["valid"] is not True else None,
           "rewritten": r.get("rewritten")}
    return row, r.get("plan") if outcome == "solved" else None


def check(dom, prob, plan, row):
    """unified-planning's verdict on mavtempo's plan, into the row."""
    res = peerslib.in_child(peerslib.check_one, (dom, prob, plan), CHECK_LIMIT)
    row["valid"] = res.get("valid")
    row["check"] = res.get("error") if row["valid"] is not True else None
    row["rewritten"] = res.get("rewritten")


def plan_stats(plan, row):
    try:
        steps = peerslib.ipc_steps(plan)
    except peerslib.PlanFormatError:
        return
    row["actions"], row["makespan"] = len(steps), round(peerslib.ipc_makespan(steps), 3)


def run_one(planner, a, folder, n, can_check):
    dom, prob = domain_file(folder, n), folder / "instances" / f"instance-{n}.pddl"
    if planner == "mavtempo":
        row, plan = run_mavtempo(a.mavtempo, dom, prob, a.time_limit)
        row["valid"], row["check"] = None, None if plan is None else "not checked: unified-planning not installed"
        if plan is not None and can_check:
            check(dom, prob, plan, row)
    else:
        row, plan = run_peer(planner, dom, prob, a.time_limit)
    row.update({"actions": None, "makespan": None})
    if plan is not None:
        plan_stats(plan, row)
        if a.plans_out:
            path = Path(a.plans_out) / planner / folder.name / f"instance-{n}.plan"
            path.parent.mkdir(parents=True, exist_ok=True)
            path.write_text(plan)
    if row["outcome"] == "solved" and row["valid"] is False:
        row["outcome"] = "rejected"
    return {"folder": folder.name, "set": folder.parent.name, "instance": n, "planner": planner, **row}


def median(values):
    return statistics.median(values) if values else None


def cell(rs):
    ok = [r for r in rs if r["outcome"] == "solved"]
    text = f"{len(ok)}/{len(rs)}"
    if ok:
        spans = [r["makespan"] for r in ok if r.get("makespan") is not None]
        text += f" ({median([r['secs'] for r in ok]):.2f} s"
        text += f", {median(spans):.1f})" if spans else ")"
    unchecked = sum(r.get("valid") is None for r in ok)
    rejected = sum(r["outcome"] == "rejected" for r in rs)
    if unchecked:
        text += f", {unchecked} n.v."
    if rejected:
        text += f", {rejected} rej."
    return text


def both_cell(rows):
    """Median times of mavtempo and LPG-td on the instances both solve."""
    by = {(r["planner"], r["instance"]): r for r in rows}
    common = [n for (p, n), r in by.items() if p == "mavtempo" and r["outcome"] == "solved"
              and by.get(("lpg", n), {}).get("outcome") == "solved"]
    if not common:
        return "–"
    m = median([by[("mavtempo", n)]["secs"] for n in common])
    lpg = median([by[("lpg", n)]["secs"] for n in common])
    return f"{m:.2f} / {lpg:.2f} ({len(common)})"


def normalise(r):
    """Rows of the mavtempo-only runs before the peers joined (no planner, no check) in today's form."""
    r.setdefault("planner", "mavtempo")
    r.setdefault("valid", None)
    r.setdefault("check", "not checked (an earlier run)" if r["outcome"] == "solved" else None)
    r.setdefault("makespan", None)
    return r


def report(rows):
    rows = [normalise(r) for r in rows]
    planners = [p for p in PLANNERS if any(r["planner"] == p for r in rows)]
    planners += sorted({r["planner"] for r in rows} - set(planners))
    by = {}
    for r in rows:
        by.setdefault(r["folder"], []).append(r)
    print("Solved / instances (median time s, median makespan of the solved); n.v. = solved, plan not checked "
          "(unified-planning cannot read the domain); rej. = plan rejected by the validator (not solved).\n")
    heads = [TITLES.get(p, p) for p in planners]
    extra = ["mavtempo / LPG-td median s where both solve"] if {"mavtempo", "lpg"} <= set(planners) else []
    extra += ["mavtempo no plan / refused / timeout / error"] if "mavtempo" in planners else []
    print("| domain | " + " | ".join(heads + extra) + " |")
    print("|---|" + "---|" * (len(heads) + len(extra)))
    totals = {p: [0, 0] for p in planners}
    for folder in sorted(by):
        rs = by[folder]
        cells = []
        for p in planners:
            mine = [r for r in rs if r["planner"] == p]
            cells.append(cell(mine) if mine else "–")
            totals[p][0] += sum(r["outcome"] == "solved" for r in mine)
            totals[p][1] += len(mine)
        if extra and extra[0].startswith("mavtempo /"):
            cells.append(both_cell(rs))
        if "mavtempo" in planners:
            mine = [r for r in rs if r["planner"] == "mavtempo"]
            cells.append(" / ".join(str(sum(r["outcome"] == o for r in mine))
                                    for o in ("no-plan", "refused", "timeout", "error")))
        print(f"| {folder} | " + " | ".join(cells) + " |")
    print("| **all** | " + " | ".join([f"**{s}/{n}**" for s, n in totals.values()] + [""] * len(extra)) + " |")
    mine = {(r["folder"], r["instance"]): r for r in rows if r["planner"] == "mavtempo"}
    solved_by_peer = {(r["folder"], r["instance"]) for r in rows
                      if r["planner"] != "mavtempo" and r["outcome"] == "solved"}
    bad = [r for k, r in sorted(mine.items()) if r["outcome"] == "no-plan"]
    if bad:
        print("\nmavtempo declared infeasible:")
        for r in bad:
            peer = " (a peer solves it)" if (r["folder"], r["instance"]) in solved_by_peer else ""
            print(f"- {r['folder']} p{r['instance']}{peer}: {r['reason']}")
    through = [r for r in rows if r.get("rewritten") and r.get("valid") is not None]
    if through:
        print("\nChecked through the rewrite (benches/peers/uprewrite.py: unified-planning cannot read the files as "
              "they are):")
        for (folder, planner), rs in sorted(group_by(through, lambda r: (r["folder"], r["planner"])).items()):
            ns = ",".join(f"p{r['instance']}" for r in sorted(rs, key=lambda r: r["instance"]))
            print(f"- {folder} {planner} {ns}: {rs[0]['rewritten']}")
    unchecked = [r for r in rows if r["outcome"] == "solved" and r.get("valid") is None]
    if unchecked:
        print("\nSolved, plan not checked by unified-planning:")
        for r in unchecked:
            print(f"- {r['folder']} p{r['instance']} {r['planner']}: {' '.join(str(r.get('check')).split())[:160]}")
    rejected = [r for r in rows if r["outcome"] == "rejected"]
    if rejected:
        print("\nPlans rejected by the validator:")
        for r in rejected:
            print(f"- {r['folder']} p{r['instance']} {r['planner']}: {' '.join(str(r.get('check')).split())[:200]}")


def group_by(rows, key):
    out = {}
    for r in rows:
        out.setdefault(key(r), []).append(r)
    return out


def read_rows(paths):
    """The rows of saved runs, the last row of each (folder, instance, planner) winning."""
    rows = {}
    for path in paths:
        for r in peerslib.read_jsonl(path):
            r = normalise(r)
            rows[(r["folder"], r["instance"], r["planner"])] = r
    return list(rows.values())


def parse_args():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--planners", help=f"default {','.join(PLANNERS)}; mavtempo alone without unified-planning")
    ap.add_argument("--mavtempo", default=str(ROOT / "target/release/mavtempo"))
    # ../shared/benchmarks beside the checkout (a worktree under wt/ looks one level further up).
    near = [d / "shared/benchmarks" for d in (ROOT.parent, ROOT.parent.parent)]
    ap.add_argument("--dir", default=str(next((d for d in near if d.is_dir()), near[0])))
    ap.add_argument("--instances", default="1-10")
    ap.add_argument("--time-limit", type=float, default=10.0)
    ap.add_argument("--domains", default="")
    ap.add_argument("--out", default="target/devset.jsonl")
    ap.add_argument("--merge", action="append", default=[], help="a saved run whose rows join the table")
    ap.add_argument("--plans-out", default="", help="keep each plan as DIR/<planner>/<folder>/instance-N.plan")
    ap.add_argument("--report", action="store_true")
    return ap.parse_args()


def main():
    a = parse_args()
    if a.report:
        report(read_rows(a.merge + [a.out]))
        return 0
    can_check = importlib.util.find_spec("unified_planning") is not None
    if a.planners is None:
        a.planners = ",".join(PLANNERS) if can_check else "mavtempo"
    planners = [p for p in a.planners.split(",") if p]
    unknown = [p for p in planners if p not in PLANNERS + ["aries"]]
    if unknown:
        sys.exit(f"devset.py: unknown planner {', '.join(unknown)} (known: {', '.join(PLANNERS)}, aries)")
    peers = [p for p in planners if p != "mavtempo"]
    if peers:
        if not can_check:
            sys.exit("devset.py: the peers need unified-planning: run benches/peers/devset.sh (its virtualenv)")
        peers, missing = peerslib.available(peers)
        for name, why in missing.items():
            print(f"# {name}: not available ({why})", file=sys.stderr)
        planners = [p for p in planners if p == "mavtempo" or p in peers]
    elif not can_check:
        print("# unified-planning not installed: mavtempo's plans are not checked", file=sys.stderr)
    lo, _, hi = a.instances.partition("-")
    instances = range(int(lo), int(hi or lo) + 1)
    chosen = folders(a.dir, [w for w in a.domains.split(",") if w])
    if not chosen:
        sys.exit(f"devset.py: no benchmark folder under {a.dir}")
    rows = [r for r in read_rows(a.merge) if r["planner"] not in planners]
    Path(a.out).parent.mkdir(parents=True, exist_ok=True)
    with open(a.out, "w") as f:
        for folder in chosen:
            for n in instances:
                if not (folder / "instances" / f"instance-{n}.pddl").is_file():
                    continue
                for planner in planners:
                    r = run_one(planner, a, folder, n, can_check)
                    rows.append(r)
                    f.write(json.dumps(r) + "\n")
                    f.flush()
                    valid = {True: "valid", False: "REJECTED", None: "n.v."}[r["valid"]] if r["makespan"] else ""
                    print(f"{r['folder']} p{n} {planner}: {r['outcome']} {r['secs']} s {valid}", file=sys.stderr)
    report(rows)
    return 0


if __name__ == "__main__":
    sys.exit(main())
