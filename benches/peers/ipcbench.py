"""The IPC-2002 benchmark files (Rovers and Satellite, SimpleTime and Time) and mavtempo's plans of them in the
layout of `mavtempo bench ipc --plans-out DIR`, checked by unified-planning's validator.

Layout: <dir>/<domain>-time[-simple]-automatic/{domain.pddl,instances/instance-N.pddl}; plans:
<plans>/<that folder name>/instance-N.plan (IPC format, `0.000: (navigate rover0 waypoint3 waypoint0) [5.000]`).
"""

import re
from collections import namedtuple
from pathlib import Path

import peerslib

DOMAINS = ["rovers", "satellite"]
# variant -> folder suffix (SimpleTime: fixed durations; Time: numeric fluents, durations read from them).
VARIANTS = {"simple": "-time-simple-automatic", "time": "-time-automatic"}

Benchmark = namedtuple("Benchmark", "domain variant instance folder domain_file problem_file")


def instance_range(text):
    """`1-10` or `1,3,5-7` -> [1, ..., 10]; ValueError on anything else."""
    out = []
    for part in text.split(","):
        m = re.fullmatch(r"\s*(\d+)\s*(?:-\s*(\d+)\s*)?", part)
        if not m:
            raise ValueError(f"instances: {part!r} is not N or N-M")
        lo, hi = int(m.group(1)), int(m.group(2) or m.group(1))
        if hi < lo:
            raise ValueError(f"instances: {part!r} is an empty range")
        out.extend(range(lo, hi + 1))
    return sorted(set(out))


def names(text, known, what):
    """A comma-separated list checked against `known`; ValueError naming the unknown ones."""
    chosen = [w.strip() for w in text.split(",") if w.strip()]
    unknown = [w for w in chosen if w not in known]
    if unknown:
        raise ValueError(f"unknown {what} {', '.join(unknown)} (known: {', '.join(known)})")
    return chosen


def benchmarks(root, domains, variants, instances):
    """The Benchmarks asked for, in domain, variant, instance order; FileNotFoundError naming a missing file."""
    out = []
    for dom in domains:
        for var in variants:
            folder = dom + VARIANTS[var]
            dfile = Path(root) / folder / "domain.pddl"
            if not dfile.is_file():
                raise FileNotFoundError(f"{dfile}: no such file (is {root} the IPC-2002 directory?)")
            for n in instances:
                pfile = Path(root) / folder / "instances" / f"instance-{n}.pddl"
                if not pfile.is_file():
                    raise FileNotFoundError(f"{pfile}: no such file")
                out.append(Benchmark(dom, var, n, folder, dfile, pfile))
    return out


def plan_path(plans_dir, b):
    return Path(plans_dir) / b.folder / f"instance-{b.instance}.plan"


def label(b):
    return f"{b.domain} {b.variant} p{b.instance}"


def check_plan(b, text, problem=None):
    """unified-planning's verdict on an IPC plan text of benchmark `b` (peerslib.check_text)."""
    return peerslib.check_text(b.domain_file, b.problem_file, text, problem)


def bench_rows(rows, benches, plans_dir=None):
    """`mavtempo bench ipc --json` lines in the peers' row format (planner "mavtempo"), for the Benchmarks in
    `benches` only; with `plans_dir` (its --plans-out) every solved plan is checked by unified-planning's
    validator. Rows already in that format (planner given: checked before) pass through. Time: reading and
    translating the PDDL plus the search."""
    by_key = {(b.domain, b.variant, b.instance): b for b in benches}
    out = []
    for j in rows:
        b = by_key.get((j.get("domain"), j.get("variant"), j.get("instance")))
        if b is None:
            continue
        if "planner" in j:
            out.append(j)
            continue
        r = {"domain": b.domain, "variant": b.variant, "instance": b.instance, "planner": "mavtempo",
             "status": "SOLVED_SATISFICING" if j.get("solved") else "NOT_SOLVED",
             "ms": (j.get("ms") or 0) + (j.get("prepare_ms") or 0), "search_ms": j.get("ms"),
             "prepare_ms": j.get("prepare_ms"), "makespan": j.get("makespan"), "actions": j.get("actions"),
             "valid": None, "validator": None, "error": j.get("reason")}
        if j.get("solved") and plans_dir is not None:
            r.update(check_plan_file(b, plan_path(plans_dir, b)))
        out.append(r)
    return out


def check_plan_file(b, path, problem=None):
    """check_plan on a plan file; a missing file is a rejection (the run said it solved the instance)."""
    try:
        text = Path(path).read_text()
    except OSError as e:
        return {"valid": False, "validator": None, "error": f"no plan: {e}"}
    return check_plan(b, text, problem)
