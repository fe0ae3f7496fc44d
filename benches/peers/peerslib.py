"""What the peer scripts share: unified-planning's engines, LPG-td through its own command line, plans in the
IPC text format, unified-planning's plan validator, and one planner run in a child process killed past its limit.

Used by run_peers.py (the suite's problems), run_ipc.py (IPC-2002 beside the peers) and validate_ipc.py (CI:
mavtempo's IPC plans checked by an independent validator). unified-planning is imported inside the functions, so
the scripts print their usage and errors without it.
"""

import itertools
import json
import multiprocessing as mp
import re
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

# unified-planning's own validator first; Kairos' validator (through unified-planning) where it cannot.
VALIDATORS = ["up_time_triggered_validator", "kairos-val"]

SOLVED = ("SOLVED_SATISFICING", "SOLVED_OPTIMALLY")

# One step of a temporal plan in the IPC format: `0.000: (navigate rover0 waypoint3 waypoint0) [5.000]`
# (LPG-td writes `0.0003:   (MOVE BASE T2) [84.1300]`).
IPC_STEP = re.compile(r"^\s*(\d+(?:\.\d*)?)\s*:\s*\(([^()]*)\)\s*\[(\d+(?:\.\d*)?)\]")


class PlanFormatError(ValueError):
    """A plan text that is not an IPC temporal plan, or names what the problem lacks."""


def environment(up_shortcuts):
    """unified-planning's environment, quiet, with the engines it does not register by itself."""
    env = up_shortcuts.get_environment()
    env.credits_stream = None
    for name, (module, cls) in EXTRA_ENGINES.items():
        if name not in env.factory.engines:
            try:
                env.factory.add_engine(name, module, cls)
            except Exception:  # not installed: reported when that engine is asked for
                pass
    return env


def read_problem(domain_file, problem_file):
    """unified-planning's reading of the PDDL files, the metric cleared: satisficing runs take the first plan each
    planner finds (the metric would make some run anytime until the limit)."""
    return read_noted(domain_file, problem_file)[0]


def read_noted(domain_file, problem_file):
    """(problem, rewrite) as read_problem; where unified-planning cannot read the files as they are, it reads
    them through uprewrite's semantics-preserving rewrite and `rewrite` is (notes, actions whose ?duration was
    rewritten), else None."""
    warnings.filterwarnings("ignore")
    from unified_planning.io import PDDLReader

    try:
        problem = PDDLReader().parse_problem(str(domain_file), str(problem_file))
        rewrite = None
    except Exception as first:
        import tempfile

        import uprewrite

        try:
            dom, prob, notes, acts = uprewrite.rewrite(Path(domain_file).read_text(), Path(problem_file).read_text())
        except Exception:
            raise first from None
        if not notes:
            raise first
        with tempfile.TemporaryDirectory() as tmp:
            (Path(tmp) / "domain.pddl").write_text(dom)
            (Path(tmp) / "problem.pddl").write_text(prob)
            problem = PDDLReader().parse_problem(str(Path(tmp) / "domain.pddl"), str(Path(tmp) / "problem.pddl"))
        rewrite = (notes, acts)
        # The functions the rewrite declares start at 0 (each is assigned before it is read).
        for f in problem.fluents:
            if f.name.startswith(uprewrite.DURATION_FUNCTION):
                for args in itertools.product(*(problem.objects(p.type) for p in f.signature)):
                    problem.set_initial_value(f(*args), 0)
    problem.clear_quality_metrics()
    return problem, rewrite


def note_rewrite(res, rewrite, steps):
    """Records in `res` that the plan is checked through the rewrite; False when the rewrite cannot check this
    plan (a rewritten action overlapping itself: its duration function would be overwritten)."""
    if rewrite is None:
        return True
    import uprewrite

    notes, acts = rewrite
    res["rewritten"] = "; ".join(notes)
    overlap = uprewrite.self_overlap(steps, set(acts))
    if overlap:
        res["error"] = f"not validated: the rewrite cannot check it: {overlap}"
        return False
    return True


def ipc_steps(text):
    """[(start, action name, [argument names], duration)] of an IPC plan text, names lower-cased (PDDL names are
    case-insensitive; unified-planning's reader lower-cases them). Lines that are no step (comments, LPG-td's
    header) are skipped; a line that starts like a step but is malformed raises PlanFormatError."""
    steps = []
    for number, line in enumerate(text.splitlines(), 1):
        m = IPC_STEP.match(line)
        if not m:
            if re.match(r"^\s*\d", line):
                raise PlanFormatError(f"line {number}: not `start: (action args) [duration]`: {line.strip()}")
            continue
        words = m.group(2).lower().split()
        if not words:
            raise PlanFormatError(f"line {number}: no action name: {line.strip()}")
        steps.append((Fraction(m.group(1)), words[0], words[1:], Fraction(m.group(3))))
    return steps


def ipc_makespan(steps):
    return float(max(s + d for s, _, _, d in steps)) if steps else 0.0


# A written duration this close to the one the domain fixes on static values is taken as that value: the IPC
# format writes decimals, and 11/9 s (Depots Time's `(/ (weight ?y) (power ?x))`) has none; unified-planning's
# validator compares durations exactly (VAL allows a tolerance too).
DURATION_TOLERANCE = Fraction(1, 1000)


def ipc_plan(problem, text):
    """The unified-planning TimeTriggeredPlan of an IPC plan text, for `problem`."""
    import unified_planning as upf

    timed = []
    static = set(problem.get_static_fluents())
    for start, name, args, dur in ipc_steps(text):
        if not problem.has_action(name):
            raise PlanFormatError(f"no action {name!r} in the domain")
        missing = [a for a in args if not problem.has_object(a)]
        if missing:
            raise PlanFormatError(f"({name} {' '.join(args)}): no object {', '.join(missing)} in the problem")
        objects = [problem.object(a) for a in args]
        exact = fixed_duration(problem, static, problem.action(name), objects)
        if exact is not None and abs(exact - dur) <= DURATION_TOLERANCE:
            dur = exact
        timed.append((start, upf.plans.ActionInstance(problem.action(name), objects), dur))
    return upf.plans.TimeTriggeredPlan(timed)


def fixed_duration(problem, static, action, objects):
    """The duration the domain fixes for `action` on `objects` (a Fraction), when `(= ?duration e)` reads only
    static functions; else None."""
    d = getattr(action, "duration", None)
    if d is None or d.lower is not d.upper or d.is_left_open() or d.is_right_open():
        return None
    env = problem.environment
    if any(f.fluent() not in static for f in env.free_vars_extractor.get(d.lower)):
        return None
    em = env.expression_manager
    e = d.lower.substitute({em.ParameterExp(p): em.ObjectExp(o) for p, o in zip(action.parameters, objects)})
    e = env.simplifier.simplify(e.substitute(problem.initial_values))
    if not (e.is_int_constant() or e.is_real_constant()):
        return None
    return Fraction(e.constant_value())


def _decimal(q):
    """A Fraction as a short exact-enough decimal (LPG-td's 4 decimals survive)."""
    return f"{float(q):.6f}".rstrip("0").rstrip(".") if q else "0"


def ipc_text(plan):
    """A unified-planning TimeTriggeredPlan in the IPC format, one step a line."""
    lines = []
    for start, ai, dur in plan.timed_actions:
        args = " ".join(str(p) for p in ai.actual_parameters)
        lines.append(f"{_decimal(start)}: ({ai.action.name}{' ' + args if args else ''}) [{_decimal(dur or 0)}]")
    return "\n".join(lines) + "\n"


def makespan(plan):
    ends = [s + (d or 0) for s, _, d in plan.timed_actions]
    return float(max(ends)) if ends else 0.0


def validate(up, problem, plan, res, validators=VALIDATORS):
    """Sets res["valid"] and res["validator"]; None when no validator could check the plan."""
    for name in validators:
        try:
            with up.PlanValidator(name=name) as v:
                # The suite's problems leave travel-time undefined from a place to itself (no path there): the
                # only feature the built-in validator does not declare, and never read by a valid plan.
                v.skip_checks = True
                vr = v.validate(problem, plan)
        except Exception as e:
            res.setdefault("validator_errors", []).append(f"{name}: {type(e).__name__}: {str(e)[:150]}")
            continue
        res["validator"] = name
        res["valid"] = vr.status.name == "VALID"
        if not res["valid"]:
            res["error"] = f"validator {name}: {rejection(vr)}"
        return
    res["validator"] = None


def rejection(vr):
    """Why a validator rejected a plan: the reason, the step it could not apply, its messages."""
    why = vr.reason.name if vr.reason is not None else "INVALID"
    if vr.inapplicable_action is not None:
        why += f" at ({vr.inapplicable_action})"
    msgs = [m.message for m in vr.log_messages or []]
    return why + (f": {' | '.join(msgs)}" if msgs else "")


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


def lpg_cli(domain_file, problem_file, limit):
    """LPG-td on the PDDL files themselves: its unified-planning wrapper neither declares timed initial
    literals nor reads LPG-td's plan lines (`0.0003:   (MOVE BASE T2) [84.1300])`). Returns (status name,
    plan text or None, messages, ms)."""
    import subprocess
    import tempfile

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
        return "SOLVED_SATISFICING", out.read_text(), [], ms


def empty_result():
    return {"status": None, "ms": None, "makespan": None, "actions": None, "valid": None, "error": None}


def _solve_lpg(domain_file, problem_file, limit, res):
    """LPG-td first, then unified-planning's reading for the validation: a plan of a domain unified-planning
    cannot read is still reported (solved, not validated)."""
    import unified_planning.shortcuts as up

    status, text, msgs, ms = lpg_cli(domain_file, problem_file, limit)
    res["status"], res["ms"] = status, ms
    if text is None:
        res["error"] = " | ".join(msgs)[:300] or None
        return
    steps = ipc_steps(text)
    res["actions"], res["makespan"], res["plan"] = len(steps), ipc_makespan(steps), text
    try:
        problem, rewrite = read_noted(domain_file, problem_file)
    except Exception as e:
        res["error"] = f"not validated: unified-planning cannot read it: {type(e).__name__}: {str(e)[:200]}"
        return
    if note_rewrite(res, rewrite, steps):
        validate(up, problem, ipc_plan(problem, text), res)


def _solve_up(planner, domain_file, problem_file, limit, res):
    """A unified-planning OneshotPlanner on unified-planning's reading of the files."""
    import unified_planning.shortcuts as up

    environment(up)
    problem, rewrite = read_noted(domain_file, problem_file)
    with up.OneshotPlanner(name=planner) as engine:
        t0 = time.perf_counter()
        r = engine.solve(problem, timeout=limit)
        ms = (time.perf_counter() - t0) * 1e3
    res["status"], res["ms"] = r.status.name, ms
    if r.status.name in SOLVED and r.plan is not None:
        res["actions"] = len(r.plan.timed_actions)
        res["makespan"] = makespan(r.plan)
        res["plan"] = ipc_text(r.plan)
        if note_rewrite(res, rewrite, ipc_steps(res["plan"])):
            validate(up, problem, r.plan, res)
    elif r.log_messages:
        res["error"] = " | ".join(m.message for m in r.log_messages)[:300]


def solve_one(planner, domain_file, problem_file, limit, queue):
    """In a child process: reads, plans, validates; puts one result dict on `queue` (with the plan's IPC text
    under "plan" when there is one)."""
    warnings.filterwarnings("ignore")
    res = empty_result()
    try:
        import unified_planning.shortcuts as up

        environment(up)
        if planner == "lpg":
            _solve_lpg(domain_file, problem_file, limit, res)
        else:
            _solve_up(planner, domain_file, problem_file, limit, res)
    except Exception as e:
        res["status"] = "ERROR"
        res["error"] = f"{type(e).__name__}: {str(e)[:300]}"
    queue.put(res)


def run_one(planner, domain_file, problem_file, limit):
    """One planner on one problem in a child process, killed 5 s past the limit (reading the PDDL and starting
    the engine come on top of it; not every engine keeps its limit)."""
    return in_child(solve_one, (planner, domain_file, problem_file, limit), limit + 5)


def in_child(target, args, limit):
    """`target(*args, queue)` in a child process that puts one result dict on the queue; killed past `limit`
    seconds (a result dict with status KILLED), or CRASHED when it ended without a result."""
    q = mp.Queue()
    p = mp.Process(target=target, args=(*args, q))
    t0 = time.perf_counter()
    p.start()
    deadline = time.monotonic() + limit
    # The queue is read before joining: a child blocks on exit until a large result (a plan) is drained.
    result, gone = None, False
    while result is None and time.monotonic() < deadline and not gone:
        gone = not p.is_alive()  # one more read after it ended: its result may be in flight
        try:
            result = q.get(timeout=0.2)
        except Exception:
            pass
    killed = p.is_alive()
    if killed:
        p.kill()
    p.join()
    if result is not None:
        return result
    res = empty_result()
    if killed:
        res.update({"status": "KILLED", "ms": (time.perf_counter() - t0) * 1e3,
                    "error": "still running past the limit"})
    else:
        res.update({"status": "CRASHED", "error": f"exit code {p.exitcode}"})
    return res


def check_text(domain_file, problem_file, text, problem=None):
    """unified-planning's verdict on an IPC plan text: a dict with "valid" (True, False, or None when it could
    not check: it cannot read the domain, or no validator could), "validator", "error", and "actions" and
    "makespan" of a well-formed plan. `problem`: the files already read (else read here)."""
    import unified_planning.shortcuts as up

    res = {"valid": None, "validator": None, "error": None}
    try:
        steps = ipc_steps(text)
        rewrite = None
        if problem is None:
            problem, rewrite = read_noted(domain_file, problem_file)
        plan = ipc_plan(problem, text)
    except PlanFormatError as e:
        res.update(valid=False, error=f"malformed plan: {e}")
        return res
    except Exception as e:
        res["error"] = f"unified-planning cannot read it: {type(e).__name__}: {str(e)[:200]}"
        return res
    res["actions"], res["makespan"] = len(steps), ipc_makespan(steps)
    if not note_rewrite(res, rewrite, steps):
        return res
    validate(up, problem, plan, res)
    if res["validator"] is None:
        res["error"] = "no validator could check it: " + "; ".join(res.get("validator_errors", []))
    return res


def check_one(domain_file, problem_file, text, queue):
    """check_text in a child process (see in_child): unified-planning may take long on a large problem."""
    warnings.filterwarnings("ignore")
    try:
        res = check_text(domain_file, problem_file, text)
    except Exception as e:
        res = {"valid": None, "validator": None, "error": f"{type(e).__name__}: {str(e)[:300]}"}
    queue.put(res)


def solved(r, limit):
    return (r["status"] in SOLVED and r["valid"] is not False
            and r["ms"] is not None and r["ms"] <= limit * 1e3)


def available(planners):
    """The planners whose engine can be made here, and why the others cannot."""
    warnings.filterwarnings("ignore")
    import unified_planning.shortcuts as up

    env = environment(up)
    ok, missing = [], {}
    for name in planners:
        try:
            if name == "lpg":
                lpg_binary()
            else:
                env.factory.engine(name)
            ok.append(name)
        except Exception as e:
            missing[name] = f"{type(e).__name__}: {str(e)[:200]}"
    return ok, missing


def fmt_ms(v):
    if v is None:
        return "–"
    return f"{v:.0f} ms" if v < 1000 else f"{v / 1e3:.1f} s"


def read_jsonl(path):
    """The JSON objects of a JSONL file; a line that is not JSON raises ValueError naming the file and line."""
    rows = []
    with open(path) as f:
        for number, line in enumerate(f, 1):
            if not line.strip():
                continue
            try:
                rows.append(json.loads(line))
            except ValueError as e:
                raise ValueError(f"{path}:{number}: not JSON ({e}): {line.strip()[:120]}") from None
    return rows
