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
import multiprocessing as mp
import re
import statistics
import sys
import time
import warnings
from fractions import Fraction
from pathlib import Path

# ENHSP (up-enhsp) plans without durative actions, so it has nothing to run here.
PLANNERS = ["lpg", "tamer", "aries", "kairos"]

# Engines that unified-planning does not register by itself: (module, class).
EXTRA_ENGINES = {
    "kairos": ("up_kairos.engine", "KairosEngine"),
    "kairos-val": ("up_kairos.engine", "KairosValidator"),
}


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


def _env(up_shortcuts):
    env = up_shortcuts.get_environment()
    env.credits_stream = None
    for name, (module, cls) in EXTRA_ENGINES.items():
        if name not in env.factory.engines:
            try:
                env.factory.add_engine(name, module, cls)
            except Exception:  # not installed: reported when that planner is asked for
                pass
    return env


def makespan(plan):
    ends = [s + (d or 0) for s, _, d in plan.timed_actions]
    return float(max(ends)) if ends else 0.0


# unified-planning's own validator first; Kairos' validator (through unified-planning) where it cannot.
VALIDATORS = ["up_time_triggered_validator", "kairos-val"]


def validate(up, problem, plan, res):
    """Sets res["valid"] and res["validator"]; None when no validator could check the plan."""
    for name in VALIDATORS:
        try:
            with up.PlanValidator(name=name) as v:
                # The problems leave travel-time undefined from a place to itself (no path there): the only
                # feature the built-in validator does not declare, and never read by a valid plan.
                v.skip_checks = True
                vr = v.validate(problem, plan)
        except Exception as e:
            res.setdefault("validator_errors", []).append(f"{name}: {type(e).__name__}: {str(e)[:150]}")
            continue
        res["validator"] = name
        res["valid"] = vr.status.name == "VALID"
        if not res["valid"]:
            res["error"] = f"validator {name}: {vr.reason}"
        return
    res["validator"] = None


def lpg_binary():
    """The LPG-td executable that up-lpg ships, found without importing up_lpg."""
    import importlib.util

    spec = importlib.util.find_spec("up_lpg")
    if spec is None or not spec.submodule_search_locations:
        raise FileNotFoundError("up-lpg is not installed")
    exe = Path(list(spec.submodule_search_locations)[0]) / "lpg"
    if not exe.exists():
        raise FileNotFoundError(f"{exe} missing")
    return exe


LPG_STEP = re.compile(r"^\s*([\d.]+):\s*\(([^()]*)\)\s*\[([\d.]+)\]")


def lpg_cli(problem, domain_file, problem_file, limit):
    """LPG-td on the PDDL files themselves: its unified-planning wrapper neither declares timed initial
    literals nor reads LPG-td's plan lines (`0.0003:   (MOVE BASE T2) [84.1300])`). Returns (status name,
    plan or None, messages, ms)."""
    import subprocess
    import tempfile

    import unified_planning as upf

    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "plan"
        cmd = [str(lpg_binary()), "-o", str(domain_file), "-f", str(problem_file), "-n", "1", "-seed", "1",
               "-cputime", str(int(max(1, limit))), "-out", str(out)]
        t0 = time.perf_counter()
        try:
            proc = subprocess.run(cmd, capture_output=True, text=True, timeout=limit + 1)
        except subprocess.TimeoutExpired:
            return "TIMEOUT", None, [], (time.perf_counter() - t0) * 1e3
        ms = (time.perf_counter() - t0) * 1e3
        if not out.exists():
            tail = (proc.stdout + proc.stderr).strip().splitlines()[-3:]
            return ("TIMEOUT" if ms >= limit * 1e3 else "UNSOLVABLE_INCOMPLETELY"), None, tail, ms
        steps = []
        for line in out.read_text().splitlines():
            m = LPG_STEP.match(line)
            if not m:
                continue
            name, *args = m.group(2).lower().split()
            act = problem.action(name)
            objs = [problem.object(a) for a in args]
            steps.append((Fraction(m.group(1)), upf.plans.ActionInstance(act, objs), Fraction(m.group(3))))
        return "SOLVED_SATISFICING", upf.plans.TimeTriggeredPlan(steps), [], ms


def solve_one(planner, domain_file, problem_file, limit, queue):
    """In a child process: reads, plans, validates; puts one result dict on `queue`."""
    warnings.filterwarnings("ignore")
    res = {"status": None, "ms": None, "makespan": None, "actions": None, "valid": None, "error": None}
    try:
        import unified_planning.shortcuts as up
        from unified_planning.engines import PlanGenerationResultStatus as S
        from unified_planning.io import PDDLReader

        _env(up)
        problem = PDDLReader().parse_problem(str(domain_file), str(problem_file))
        # Satisficing runs: the first plan each planner finds (the metric would make some run anytime
        # until the limit).
        problem.clear_quality_metrics()
        if planner == "lpg":
            status, plan, msgs, ms = lpg_cli(problem, domain_file, problem_file, limit)
        else:
            with up.OneshotPlanner(name=planner) as engine:
                t0 = time.perf_counter()
                r = engine.solve(problem, timeout=limit)
                ms = (time.perf_counter() - t0) * 1e3
            status, plan = r.status.name, r.plan
            msgs = [m.message for m in r.log_messages or []]
        res["status"], res["ms"] = status, ms
        if status in (S.SOLVED_SATISFICING.name, S.SOLVED_OPTIMALLY.name) and plan is not None:
            res["actions"] = len(plan.timed_actions)
            res["makespan"] = makespan(plan)
            validate(up, problem, plan, res)
        elif msgs:
            res["error"] = " | ".join(msgs)[:300]
    except Exception as e:
        res["status"] = "ERROR"
        res["error"] = f"{type(e).__name__}: {str(e)[:300]}"
    queue.put(res)


def run_one(planner, domain_file, problem_file, limit):
    q = mp.Queue()
    p = mp.Process(target=solve_one, args=(planner, domain_file, problem_file, limit, q))
    t0 = time.perf_counter()
    p.start()
    # Reading the PDDL and starting the engine come on top of the limit: 5 s more before it is killed.
    p.join(limit + 5)
    if p.is_alive():
        p.kill()
        p.join()
        return {"status": "KILLED", "ms": (time.perf_counter() - t0) * 1e3, "makespan": None,
                "actions": None, "valid": None, "error": "still running past the limit"}
    try:
        return q.get(timeout=1)
    except Exception:
        return {"status": "CRASHED", "ms": None, "makespan": None, "actions": None, "valid": None,
                "error": f"exit code {p.exitcode}"}


def solved(r, limit):
    return (r["status"] in ("SOLVED_SATISFICING", "SOLVED_OPTIMALLY") and r["valid"] is not False
            and r["ms"] is not None and r["ms"] <= limit * 1e3)


def available(planners):
    """The planners whose engine can be made here, and why the others cannot."""
    warnings.filterwarnings("ignore")
    import unified_planning.shortcuts as up

    env = _env(up)
    ok, missing = [], {}
    for name in planners:
        try:
            if name == "lpg":
                lpg_binary()
                ok.append(name)
                continue
            env.factory.engine(name)
            ok.append(name)
        except Exception as e:
            missing[name] = f"{type(e).__name__}: {str(e)[:200]}"
    return ok, missing


def fmt_ms(v):
    if v is None:
        return "–"
    return f"{v:.0f} ms" if v < 1000 else f"{v / 1e3:.1f} s"


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
        with open(args.out) as f:
            rows = [json.loads(line) for line in f if line.strip()]
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
