"""uprewrite keeps unified-planning's verdicts: plans of ZenoTravel Time and Rovers Time, which it cannot read as
written, are accepted through the rewrite when valid and rejected when their fuel or energy runs short or a
duration is wrong (issue 32). Run in the peers' virtualenv:

    target/peers-venv/bin/python -m unittest discover -s benches/peers -p 'test_uprewrite.py'
"""

import sys
import unittest
from fractions import Fraction
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import peerslib  # noqa: E402
import uprewrite  # noqa: E402

BENCH = Path(__file__).resolve().parents[3] / "shared" / "benchmarks" / "ipc2002"
if not BENCH.is_dir():
    BENCH = Path(__file__).resolve().parents[2] / ".." / "shared" / "benchmarks" / "ipc2002"


def files(folder, n):
    d = BENCH / folder
    return d / "domain.pddl", d / "instances" / f"instance-{n}.pddl"


def plan_text(steps):
    """IPC text of [(action words, duration)] run one after the other, 10 ms apart."""
    t, lines = Fraction(0), []
    for words, dur in steps:
        lines.append(f"{float(t):.3f}: ({words}) [{float(dur):.6f}]")
        t += Fraction(dur) + Fraction(1, 100)
    return "\n".join(lines) + "\n"


def check(folder, n, steps):
    return peerslib.check_text(*files(folder, n), plan_text(steps))


# ZenoTravel Time p2: plane1 (fuel 1773, slow-burn 3) must refuel before flying city0 -> city2 (998 km).
ZENO = [("refuel plane1 city0", Fraction(6830 - 1773, 470)),
        ("fly plane1 city0 city2", None), ("board person1 plane1 city2", "0.3"),
        ("fly plane1 city2 city1", None), ("debark person1 plane1 city1", "0.6"),
        ("fly plane1 city1 city2", None)]


def zeno_steps(drop_refuel=False, stretch=1):
    """The plan, each fly's duration distance / slow-speed read from the problem (times `stretch`)."""
    _, prob = files("zenotravel-time-automatic", 2)
    text = prob.read_text()
    import re

    def value(expr):
        return Fraction(re.search(r"\(= \(" + re.escape(expr) + r"\) (\d+)\)", text).group(1))

    out = []
    for words, dur in ZENO:
        if drop_refuel and words.startswith("refuel"):
            continue
        if dur is None:
            _, plane, a, b = words.split()
            dur = value(f"distance {a} {b}") / value(f"slow-speed {plane}") * stretch
        out.append((words, dur))
    return out


# Rovers Time p1 (rover0: energy 50, recharge-rate 11, at waypoint3; waypoint0 in the sun): the plan mavtempo
# finds (41 energy), after a trip to waypoint0, a recharge to 80 and `k` navigations back and forth.
ROVERS_TAIL = [("calibrate rover0 camera0 objective1 waypoint3", 5),
               ("take_image rover0 waypoint3 objective1 camera0 high_res", 7),
               ("communicate_image_data rover0 general objective1 high_res waypoint3 waypoint0", 15),
               ("sample_rock rover0 rover0store waypoint3", 8), ("drop rover0 rover0store", 1),
               ("navigate rover0 waypoint3 waypoint1", 5), ("navigate rover0 waypoint1 waypoint2", 5),
               ("sample_soil rover0 rover0store waypoint2", 10),
               ("communicate_soil_data rover0 general waypoint2 waypoint2 waypoint0", 10),
               ("communicate_rock_data rover0 general waypoint3 waypoint2 waypoint0", 10)]


def rovers_steps(k, recharge=Fraction(80 - 42, 11)):
    steps = [("navigate rover0 waypoint3 waypoint0", 5)]
    if recharge is not None:
        steps.append(("recharge rover0 waypoint0", recharge))
    for i in range(k):
        steps.append(("navigate rover0 waypoint0 waypoint3" if i % 2 == 0 else "navigate rover0 waypoint3 waypoint0", 5))
    return steps + ROVERS_TAIL


class Rewrite(unittest.TestCase):
    def test_the_text_rewrites(self):
        dom, prob = files("zenotravel-time-automatic", 2)
        d, p, notes, acts = uprewrite.rewrite(dom.read_text(), prob.read_text())
        self.assertIn("(at ?x - object ?c - city)", d)
        self.assertIn("(increase (total-fuel-used)", d)
        self.assertIn("(= (total-fuel-used) 0)", p)
        self.assertEqual(acts, [])
        self.assertEqual(len(notes), 4, notes)
        self.assertIn("(>= ?duration (- (/ (- (capacity ?a) (fuel ?a)) (refuel-rate ?a)) 0.001))", d)
        dom, prob = files("rovers-time-automatic", 1)
        d, _, _, acts = uprewrite.rewrite(dom.read_text(), prob.read_text())
        self.assertEqual(acts, ["recharge"])
        self.assertNotIn("?duration (recharge-rate", d)
        self.assertIn("(at start (assign (duration-of-recharge ?x ?w) (/ (- 80 (energy ?x)) (recharge-rate ?x))))", d)

    def test_zenotravel_plans_keep_their_verdicts(self):
        ok = check("zenotravel-time-automatic", 2, zeno_steps())
        self.assertIs(ok["valid"], True, ok)
        self.assertIn("total-fuel-used", ok["rewritten"])
        no_fuel = check("zenotravel-time-automatic", 2, zeno_steps(drop_refuel=True))
        self.assertIs(no_fuel["valid"], False, no_fuel)
        wrong = check("zenotravel-time-automatic", 2, zeno_steps(stretch=2))
        self.assertIs(wrong["valid"], False, wrong)

    def test_rovers_recharge_fills_to_80_exactly(self):
        # 80 after the recharge: 3 extra navigations leave enough for the rest (80 - 24 - 41 >= 0), 5 do not.
        ok = check("rovers-time-automatic", 1, rovers_steps(3))
        self.assertIs(ok["valid"], True, ok)
        self.assertIn("recharge", ok["rewritten"])
        short = check("rovers-time-automatic", 1, rovers_steps(5))
        self.assertIs(short["valid"], False, short)
        # Without the recharge, 42 does not even cover the plan.
        self.assertIs(check("rovers-time-automatic", 1, rovers_steps(1, recharge=None))["valid"], False)
        # A recharge whose duration is not (80 - energy) / rate.
        wrong = check("rovers-time-automatic", 1, rovers_steps(3, recharge=Fraction(38, 11) + 1))
        self.assertIs(wrong["valid"], False, wrong)

    def test_a_rewritten_action_overlapping_itself_is_not_checked(self):
        steps = [(Fraction(0), "recharge", ["rover0", "waypoint0"], Fraction(3)),
                 (Fraction(1), "recharge", ["rover0", "waypoint0"], Fraction(3))]
        self.assertIsNotNone(uprewrite.self_overlap(steps, {"recharge"}))
        self.assertIsNone(uprewrite.self_overlap(steps[:1], {"recharge"}))


if __name__ == "__main__":
    unittest.main()
