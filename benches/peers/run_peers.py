#!/usr/bin/env python3
"""Runs established planners on the PDDL problems of `mavtempo bench suite --write DIR --pddl` and sets
mavtempo's own figures (`mavtempo bench suite --json`, same seeds) beside them.

For every DIR/<domain>/n<N>_s<SEED>.pddl and every planner: unified-planning's PDDLReader reads the domain
and problem, the planner gets the time limit (each run in a child process that is killed past it, as not
every engine keeps its limit: 5 s past it), and a returned plan is validated by unified-planning's plan validator. A
problem counts as solved when a plan came back within the limit and the validator did not reject it.

Output: one JSON object per (domain, size, seed, planner) in --out, and a Markdown table per domain on
standard output (solved out of the seeds and median time of the solved ones, per size and planner).

Usage: run_peers.py --problems DIR [--mavtempo FILE] [--planners lpg,tamer,...] [--time-limit 10]
                    [--out peers.jsonl]
       run_peers.py --report --out peers.jsonl      (the table again, from the saved results)
"""

import argparse
import json
import re
import statistics
import sys
from pathlib import Path

from peerslib import PLANNERS, available, fmt_ms, read_jsonl, run_one, solved


def problem_files(root):
    """(domain, size, seed, domain file, problem file), sorted by domain, size and seed."""
    out = []
    for ddir in sorted(p for p in Path(root).iterdir() if p.is_dir()):
        dom = ddir / "domain.pddl"
        if not dom.exists():
            continue
        for f in ddir.glob("n*_s*.pddl"):
            m = re.fullmatch(r"n(\d+)_s(\d+)\.pddl", f.name)
            if m:
                out.append((ddir.name, int(m.group(1)), int(m.group(2)), dom, f))
    return sorted(out, key=lambda t: (t[0], t[1], t[2]))


def table(rows, planners, limit):
    """Markdown: per domain, one line per size, `solved/problems (median)` per planner."""
    out = []
    for dom in sorted({r["domain"] for r in rows}):
        sizes = sorted({r["size"] for r in rows if r["domain"] == dom})
        cols = [p for p in planners if any(r["planner"] == p and r["domain"] == dom for r in rows)]
        out.append(f"**{dom}** (solved / problems (median time of the solved), plans the validator rejected; "
                   f"limit {limit:g} s)\n")
        out.append("| n | " + " | ".join(cols) + " |")
        out.append("|---|" + "---|" * len(cols))
        for n in sizes:
            cells = []
            for p in cols:
                rs = [r for r in rows if r["domain"] == dom and r["size"] == n and r["planner"] == p]
                ok = [r["ms"] for r in rs if r["solved"]]
                med = statistics.median(ok) if ok else None
                rejected = sum(1 for r in rs if r["valid"] is False)
                cells.append(f"{len(ok)}/{len(rs)} ({fmt_ms(med)})"
                             + (f", {rejected} rejected" if rejected else ""))
            out.append(f"| {n} | " + " | ".join(cells) + " |")
        out.append("")
    return "\n".join(out)


def mavtempo_rows(path, wanted):
    """The per-problem lines of `mavtempo bench suite --json` for the (domain, size, seed) in `wanted`."""
    rows = []
    with open(path) as f:
        for line in f:
            try:
                j = json.loads(line)
            except ValueError:
                continue
            if "seed" not in j or (j["domain"], j["size"], j["seed"]) not in wanted:
                continue
            rows.append({"domain": j["domain"], "size": j["size"], "seed": j["seed"], "planner": "mavtempo",
                         "status": "SOLVED" if j["solved"] else "NOT_SOLVED", "ms": j["ms"],
                         "makespan": None, "actions": j["actions"], "valid": j["solved"] or None,
                         "error": j.get("failure"), "solved": bool(j["solved"])})
    return rows


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--problems", help="DIR given to `mavtempo bench suite --write DIR --pddl`")
    ap.add_argument("--mavtempo", help="`mavtempo bench suite --json` output on the same seeds")
    ap.add_argument("--planners", default=",".join(PLANNERS))
    ap.add_argument("--time-limit", type=float, default=10.0)
    ap.add_argument("--out", default="peers.jsonl")
    ap.add_argument("--report", action="store_true",
                    help="only print the table of the results already in --out")
    args = ap.parse_args()

    if args.report:
        rows = read_jsonl(args.out)
        order = ["mavtempo"] + [p for p in args.planners.split(",") if p]
        order += sorted({r["planner"] for r in rows} - set(order))
        print(table(rows, order, args.time_limit))
        return

    if not args.problems:
        sys.exit("--problems DIR is needed (or --report)")
    files = problem_files(args.problems)
    if not files:
        sys.exit(f"no DIR/<domain>/n<N>_s<SEED>.pddl under {args.problems}")
    planners, missing = available([p for p in args.planners.split(",") if p])
    for name, why in missing.items():
        print(f"# {name}: not available ({why})", file=sys.stderr)

    rows = []
    with open(args.out, "w") as out:
        for dom, n, seed, dfile, pfile in files:
            for planner in planners:
                r = run_one(planner, dfile, pfile, args.time_limit)
                r.pop("plan", None)
                r.update({"domain": dom, "size": n, "seed": seed, "planner": planner})
                r["solved"] = solved(r, args.time_limit)
                rows.append(r)
                out.write(json.dumps(r) + "\n")
                out.flush()
                print(f"{dom} n={n} seed={seed} {planner}: {r['status']} {fmt_ms(r['ms'])}"
                      + (f" makespan {r['makespan']:.0f} s" if r["makespan"] is not None else "")
                      + ("" if r["valid"] is not False else " INVALID")
                      + (f" ({r['error'][:120]})" if r["error"] and not r["solved"] else ""),
                      file=sys.stderr, flush=True)
        if args.mavtempo:
            mv = mavtempo_rows(args.mavtempo, {(d, n, s) for d, n, s, _, _ in files})
            for r in mv:
                out.write(json.dumps(r) + "\n")
            rows.extend(mv)
            planners = ["mavtempo"] + planners
    print(table(rows, planners, args.time_limit))


if __name__ == "__main__":
    main()
