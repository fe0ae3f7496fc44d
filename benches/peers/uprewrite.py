"""Semantics-preserving rewrites of PDDL text that unified-planning cannot read (issue 32), so that plans of
ZenoTravel and Rovers Time can be checked by its validator. Used by peerslib.read_problem only after
unified-planning refused the original files, for every planner alike; the rows say when a plan was checked
through the rewrite. Three rewrites, each keeping the set of valid plans:

- `either` types in a predicate's or function's declaration (ZenoTravel's `(at ?x - (either person aircraft)
  ?c - city)`) widened to `object`: actions keep their typed parameters and the initial state is unchanged,
  so no plan can reach an atom the original could not have; the widening only declares more atoms.
  (`either` in an action's parameters is left alone: widening it would let more actions in.)
- a 0-ary function written without parentheses (ZenoTravel's `total-fuel-used`, allowed by PDDL 2.1) gets
  them, in the domain and the problem.
- `?duration` in an effect of an action whose duration is fixed, `(= ?duration e)` (Rovers Time's
  `recharge`): PDDL 2.1 evaluates `e` in the state at the action's start. A fresh function
  `(duration-of-<action> ?params)` is assigned `e` at the start (effects read the state before their
  happening, the state `e` is evaluated in) and read instead of `?duration`. Only that start writes it, so it
  keeps its value until the end unless the same ground action starts again meanwhile: a plan where it
  overlaps itself is not checked through the rewrite (`self_overlap`). The harness gives each such function the
  initial value 0 (it is assigned before it is read).

A duration fixed by a function actions change (`(= ?duration (/ (- (capacity ?a) (fuel ?a)) (refuel-rate ?a)))`)
has no decimal form in general, and unified-planning compares durations exactly: it becomes `e` within
1 ms, the tolerance peerslib.DURATION_TOLERANCE already gives durations fixed by static functions. (With
`?duration` in an effect the effect reads `e` itself, the exact value the written duration rounds.)

The problem's `:metric` is left out of the rewritten text: it does not decide whether a plan is valid, and
unified-planning's reader refuses ZenoTravel's.
"""

import re

DURATION_FUNCTION = "duration-of-"
ATOM = re.compile(r'"[^"]*"|[()]|[^\s()]+')


def parse(text):
    """The s-expressions of a PDDL text, comments dropped, words lower-cased (PDDL is case-insensitive)."""
    text = re.sub(r";[^\n]*", "", text)
    stack, top = [], []
    cur = top
    for tok in ATOM.findall(text):
        if tok == "(":
            stack.append(cur)
            cur = []
        elif tok == ")":
            if not stack:
                raise ValueError("unbalanced ')'")
            done, cur = cur, stack.pop()
            cur.append(done)
        else:
            cur.append(tok.lower())
    if stack:
        raise ValueError("unbalanced '('")
    return top


def dump(x):
    if isinstance(x, list):
        return "(" + " ".join(dump(y) for y in x) + ")"
    return x


def section(define, key):
    return next((s for s in define[2:] if isinstance(s, list) and s and s[0] == key), None)


def zero_ary_functions(define):
    """Names of the functions declared without parameters."""
    fs = section(define, ":functions")
    names = set()
    for f in fs[1:] if fs else []:
        if isinstance(f, list) and len(f) == 1 and isinstance(f[0], str):
            names.add(f[0])
    return names


def parenthesise(x, names, is_head=False):
    """`x` with every bare use (not a list's head) of a 0-ary function `names` made `(name)`; (new, count)."""
    if isinstance(x, str):
        return ([x], 1) if x in names and not is_head else (x, 0)
    out, n = [], 0
    for i, y in enumerate(x):
        y2, k = parenthesise(y, names, i == 0)
        out.append(y2)
        n += k
    return out, n


def widen_either(define):
    """Declarations of predicates and functions with `(either ...)` argument types widened to `object`."""
    n = 0
    for key in (":predicates", ":functions"):
        sec = section(define, key)
        for decl in sec[1:] if sec else []:
            if isinstance(decl, list):
                for i, y in enumerate(decl):
                    if isinstance(y, list) and y and y[0] == "either":
                        decl[i] = "object"
                        n += 1
    return n


def replace_duration(x, by):
    if x == "?duration":
        return by, 1
    if isinstance(x, list):
        out, n = [], 0
        for y in x:
            y2, k = replace_duration(y, by)
            out.append(y2)
            n += k
        return out, n
    return x, 0


def fixed_duration(action):
    """The `e` of an action's `:duration (= ?duration e)`, or None."""
    for i, y in enumerate(action):
        if y == ":duration" and i + 1 < len(action):
            d = action[i + 1]
            if isinstance(d, list) and len(d) == 3 and d[0] == "=" and d[1] == "?duration":
                return d[2]
    return None


def key_value(action, key):
    for i, y in enumerate(action):
        if y == key and i + 1 < len(action):
            return i + 1
    return None


def contains(x, word):
    return x == word or (isinstance(x, list) and any(contains(y, word) for y in x))


def duration_in_effects(define):
    """Rewrites `?duration` in effects (see the module's text); the names of the actions rewritten."""
    rewritten = []
    for action in define[2:]:
        if not (isinstance(action, list) and action and action[0] == ":durative-action"):
            continue
        e = fixed_duration(action)
        at = key_value(action, ":effect")
        if e is None or at is None or not contains(action[at], "?duration") or contains(e, "?duration"):
            continue
        name = action[1]
        p = key_value(action, ":parameters")
        params = action[p] if p is not None else []
        variables = [w for w in params if isinstance(w, str) and w.startswith("?")]
        fluent = [f"{DURATION_FUNCTION}{name}", *variables]
        eff, _ = replace_duration(action[at], fluent)
        assign = ["at", "start", ["assign", fluent, e]]
        action[at] = eff + [assign] if eff and eff[0] == "and" else ["and", eff, assign]
        fs = section(define, ":functions")
        if fs is None:
            fs = [":functions"]
            define.insert(next(i for i, s in enumerate(define) if isinstance(s, list) and s and s[0] in
                               (":action", ":durative-action")), fs)
        fs.append([f"{DURATION_FUNCTION}{name}", *params])
        rewritten.append(name)
    return rewritten


NUMERIC_EFFECTS = {"increase", "decrease", "assign", "scale-up", "scale-down"}
DURATION_TOLERANCE = "0.001"


def changed_functions(x, out):
    """Names of the functions numeric effects in `x` change, into `out`."""
    if isinstance(x, list):
        if len(x) == 3 and x[0] in NUMERIC_EFFECTS and isinstance(x[1], list) and x[1]:
            out.add(x[1][0])
        for y in x:
            changed_functions(y, out)
    return out


def reads_any(x, names):
    return isinstance(x, list) and bool(x) and (x[0] in names or any(reads_any(y, names) for y in x[1:]))


def tolerate_state_durations(define):
    """`(= ?duration e)` with `e` reading a function actions change, made `e` within DURATION_TOLERANCE; the
    names of those actions."""
    changed = changed_functions(define, set())
    out = []
    for action in define[2:]:
        if not (isinstance(action, list) and action and action[0] == ":durative-action"):
            continue
        e = fixed_duration(action)
        if e is None or not reads_any(e, changed):
            continue
        at = key_value(action, ":duration")
        action[at] = ["and", [">=", "?duration", ["-", e, DURATION_TOLERANCE]],
                      ["<=", "?duration", ["+", e, DURATION_TOLERANCE]]]
        out.append(action[1])
    return out


def rewrite(domain_text, problem_text):
    """(domain text, problem text, notes): the rewritten files and what was rewritten (empty: nothing)."""
    dom = parse(domain_text)
    prob = parse(problem_text)
    if len(dom) != 1 or len(prob) != 1:
        raise ValueError("one (define ...) per file")
    dom, prob = dom[0], prob[0]
    notes = []
    n = widen_either(dom)
    if n:
        notes.append(f"{n} `either` argument type(s) of predicates/functions widened to object")
    names = zero_ary_functions(dom)
    if names:
        dom, k1 = parenthesise(dom, names)
        prob, k2 = parenthesise(prob, names)
        if k1 + k2:
            notes.append(f"{k1 + k2} bare use(s) of 0-ary function(s) {', '.join(sorted(names))} parenthesised")
    metric = section(prob, ":metric")
    if metric is not None:
        # unified-planning's reader refuses some metrics (ZenoTravel's `(total-time)` beside a fluent); a
        # metric does not decide whether a plan is valid, and the harness clears it anyway.
        prob.remove(metric)
        notes.append("metric left out")
    acts = duration_in_effects(dom)
    if acts:
        notes.append(f"?duration in the effects of {', '.join(acts)} read from a function assigned at the start")
    # After duration_in_effects, which reads the `(= ?duration e)` form.
    tolerant = tolerate_state_durations(dom)
    if tolerant:
        notes.append(f"durations of {', '.join(tolerant)} (read from the state) taken within {DURATION_TOLERANCE} s")
    return dump(dom) + "\n", dump(prob) + "\n", notes, acts


def self_overlap(steps, actions):
    """A step of one of `actions` that starts while the same ground action runs: [(start, name, args, dur)]."""
    runs = {}
    for start, name, args, dur in sorted(steps):
        if name not in actions:
            continue
        key = (name, tuple(args))
        if key in runs and start < runs[key]:
            return f"{name} {' '.join(args)} overlaps itself at {float(start):.3f}"
        runs[key] = max(runs.get(key, start), start + dur)
    return None
