#!/usr/bin/env python3
"""Established planners and mavtempo on the IPC-2002 Rovers and Satellite temporal benchmarks (issue 17).

Every planner gets every instance with the same limit, one run at a time (benches/peers/peerslib.py: a child
process killed 5 s past the limit; LPG-td through its own command line), and every returned plan is checked by
unified-planning's validator. mavtempo's figures come from `mavtempo bench ipc --json` run separately
(--mavtempo-jsonl), its plans (--mavtempo-plans, the bench's --plans-out) checked by the same validator.

Output: one JSON object per (domain, variant, instance, planner) in --out, and on standard output the Markdown
tables: per domain, variant and ten instances, validated / instances (median time, median makespan of the
validated plans); per instance of SimpleTime p1-p10, the makespan and time of each validated plan.

Usage: run_ipc.py [--dir IPC2002] [--planners lpg,kairos,aries,tamer] [--time-limit 10] [--instances 1-20]
                  [--domains rovers,satellite] [--variants simple,time] [--out FILE] [--plans-out DIR]
                  [--mavtempo-jsonl FILE [--mavtempo-plans DIR] [--mavtempo-out FILE]]
       run_ipc.py --report --out FILE [--mavtempo-jsonl FILE]     (the tables again, from saved results)
With --planners '' the peers are not run and their results are read from --out.
"""

import argparse
import json
import statistics
import sys
from pathlib import Path

import ipcbench
import peerslib

ROOT = Path(__file__).resolve().parents[2]
PLANNERS = ["lpg", "kairos", "aries", "tamer"]
TITLES = {"mavtempo": "mavtempo", "lpg": "LPG-td", "kairos": "Kairos", "aries": "Aries", "tamer": "TAMER"}
VARIANT_TITLES = {"simple": "SimpleTime", "time": "Time"}


def validated(r, limit):
    return peerslib.solved(r, limit) and r["valid"] is True


def run_peers(benches, planners, limit, out_path, plans_out):
    """Every planner on every benchmark; rows written to `out_path` as they come, plans under plans_out."""
    rows = []
    with open(out_path, "w") as out:
        for b in benches:
            for planner in planners:
                r = peerslib.run_one(planner, b.domain_file, b.problem_file, limit)
                save_plan(r.pop("plan", None), plans_out, planner, b)
                r.update({"domain": b.domain, "variant": b.variant, "instance": b.instance, "planner": planner})
                r["solved"] = validated(r, limit)
                rows.append(r)
                out.write(json.dumps(r) + "\n")
                out.flush()
                progress(b, planner, r)
    return rows


def save_plan(text, plans_out, planner, b):
    if text is None or plans_out is None:
        return
    path = ipcbench.plan_path(Path(plans_out) / planner, b)
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text)


def progress(b, planner, r):
    verdict = {True: "valid", False: "REJECTED", None: "not validated"}[r["valid"]]
    line = f"{ipcbench.label(b)} {planner}: {r['status']} {peerslib.fmt_ms(r['ms'])}"
    if r["makespan"] is not None:
        line += f" makespan {r['makespan']:.1f} {verdict}"
    if r["error"] and not r.get("solved"):
        line += " (" + " ".join(r["error"].split())[:120] + ")"
    print(line, file=sys.stderr, flush=True)


def mavtempo(args, benches):
    """mavtempo's rows from its `bench ipc --json` output, checked against its plans when given."""
    rows = ipcbench.bench_rows(peerslib.read_jsonl(args.mavtempo_jsonl), benches, args.mavtempo_plans)
    for r in rows:
        r["solved"] = validated(r, args.time_limit)
    if args.mavtempo_out:
        with open(args.mavtempo_out, "w") as out:
            out.writelines(json.dumps(r) + "\n" for r in rows)
    return rows


def fmt_num(v):
    return "–" if v is None else f"{v:.0f}" if v >= 100 else f"{v:.1f}"


def median(values):
    return statistics.median(values) if values else None


def summary_cell(rs, limit):
    ok = [r for r in rs if validated(r, limit)]
    cell = f"{len(ok)}/{len(rs)}"
    if ok:
        cell += (f" ({peerslib.fmt_ms(median([r['ms'] for r in ok]))}, "
                 f"{fmt_num(median([r['makespan'] for r in ok if r['makespan'] is not None]))})")
    rejected = sum(1 for r in rs if r["valid"] is False)
    unchecked = sum(1 for r in rs if r["status"] in peerslib.SOLVED and r["valid"] is None)
    if rejected:
        cell += f", {rejected} rej."
    if unchecked:
        cell += f", {unchecked} not validated"
    return cell


def groups(instances):
    """Instances in tens: 1-10, 11-20, ..."""
    out = {}
    for n in sorted(instances):
        out.setdefault((n - 1) // 10, []).append(n)
    return list(out.values())


def summary_table(rows, planners, limit):
    cols = [p for p in planners if any(r["planner"] == p for r in rows)]
    out = [f"Validated / instances (median time, median makespan of the validated plans); rej. = plans the "
           f"validator rejected; limit {limit:g} s.\n",
           "| domain | variant | instances | " + " | ".join(TITLES.get(p, p) for p in cols) + " |",
           "|---|---|---|" + "---|" * len(cols)]
    keys = sorted({(r["domain"], r["variant"]) for r in rows}, key=lambda k: (k[0], k[1] != "simple"))
    for dom, var in keys:
        insts = {r["instance"] for r in rows if (r["domain"], r["variant"]) == (dom, var)}
        for g in groups(insts):
            cells = [summary_cell([r for r in rows if (r["domain"], r["variant"], r["planner"]) == (dom, var, p)
                                   and r["instance"] in g], limit) for p in cols]
            out.append(f"| {dom} | {VARIANT_TITLES.get(var, var)} | p{g[0]}–p{g[-1]} | " + " | ".join(cells) + " |")
    return "\n".join(out) + "\n"


def instance_cell(r, limit):
    if r is None:
        return "–"
    if validated(r, limit):
        return f"{fmt_num(r['makespan'])} ({peerslib.fmt_ms(r['ms'])})"
    return "rej." if r["valid"] is False else "–"


def instance_table(rows, planners, limit, variant="simple", instances=range(1, 11)):
    cols = [p for p in planners if any(r["planner"] == p for r in rows)]
    by_key = {(r["domain"], r["variant"], r["instance"], r["planner"]): r for r in rows}
    out = [f"{VARIANT_TITLES[variant]} p{instances[0]}–p{instances[-1]}: makespan (time) of each validated plan.\n",
           "| domain | p | " + " | ".join(TITLES.get(p, p) for p in cols) + " |",
           "|---|---|" + "---|" * len(cols)]
    for dom in sorted({r["domain"] for r in rows if r["variant"] == variant}):
        for n in instances:
            if not any((dom, variant, n, p) in by_key for p in cols):
                continue
            cells = [instance_cell(by_key.get((dom, variant, n, p)), limit) for p in cols]
            out.append(f"| {dom} | {n} | " + " | ".join(cells) + " |")
    return "\n".join(out) + "\n"


def parse_args():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--dir", default=str(ROOT / ".." / "shared" / "benchmarks" / "ipc2002"))
    ap.add_argument("--planners", default=",".join(PLANNERS))
    ap.add_argument("--time-limit", type=float, default=10.0)
    ap.add_argument("--instances", default="1-20")
    ap.add_argument("--domains", default=",".join(ipcbench.DOMAINS))
    ap.add_argument("--variants", default=",".join(ipcbench.VARIANTS))
    ap.add_argument("--out", default=str(ROOT / "benches" / "peers" / "results" / "ipc2002-peers.jsonl"))
    ap.add_argument("--plans-out", help="keep each peer's plan as DIR/<planner>/<folder>/instance-N.plan")
    ap.add_argument("--mavtempo-jsonl", help="`mavtempo bench ipc --json` output (or its checked rows)")
    ap.add_argument("--mavtempo-plans", help="the --plans-out DIR of that bench run: its plans are checked")
    ap.add_argument("--mavtempo-out", help="write mavtempo's checked rows here")
    ap.add_argument("--report", action="store_true", help="only print the tables of the saved results")
    return ap.parse_args()


def main():
    args = parse_args()
    try:
        benches = ipcbench.benchmarks(args.dir, ipcbench.names(args.domains, ipcbench.DOMAINS, "domain"),
                                      ipcbench.names(args.variants, list(ipcbench.VARIANTS), "variant"),
                                      ipcbench.instance_range(args.instances))
        planners = ipcbench.names(args.planners, PLANNERS, "planner")
        if args.report or not planners:
            keys = {(b.domain, b.variant, b.instance) for b in benches}
            rows = [r for r in peerslib.read_jsonl(args.out) if (r["domain"], r["variant"], r["instance"]) in keys]
            planners = planners or PLANNERS
        else:
            planners, missing = peerslib.available(planners)
            for name, why in missing.items():
                print(f"# {name}: not available ({why})", file=sys.stderr)
            rows = run_peers(benches, planners, args.time_limit, args.out, args.plans_out)
        if args.mavtempo_jsonl:
            rows = mavtempo(args, benches) + rows
    except (OSError, ValueError, KeyError) as e:
        sys.exit(f"run_ipc.py: {e}")
    order = ["mavtempo"] + planners
    print(summary_table(rows, order, args.time_limit))
    print(instance_table(rows, order, args.time_limit))


if __name__ == "__main__":
    main()
