"""pymoo references for paraflex's optimization core (src/optimize), written to
reference/optimize/*.json with their provenance (pymoo version, seeds, settings):

- hypervolume.json: pymoo's hypervolume indicator (pymoo.indicators.hv.HV) on fixed point
  sets (2 and 3 objectives, seeded uniform points, some outside the reference box);
- nsga2_zdt.json: pymoo's NSGA-II with its defaults (SBX eta 15 prob 0.9, PM eta 20,
  binary crowded tournament, rank-and-crowding survival) on ZDT1-3 with 30 variables at two
  budgets over several seeds: the hypervolume of every design the run evaluated
  (its archive) and of its final population's front;
- nsga2_mixed.json: pymoo's mixed-variable GA with rank-and-crowding survival (its mixed
  NSGA-II: SBX/PM with RoundingRepair on Integer variables) on a continuous/integer toy problem.

Run by `make reference-pymoo` (installs tools/optimize/requirements.txt into .venv).
"""

import argparse
import json
import platform
import time
from pathlib import Path

import numpy as np
import pymoo
from pymoo.algorithms.moo.nsga2 import NSGA2, RankAndCrowding
from pymoo.core.mixed import MixedVariableGA
from pymoo.core.problem import ElementwiseProblem
from pymoo.core.variable import Integer, Real
from pymoo.indicators.hv import HV
from pymoo.optimize import minimize
from pymoo.problems import get_problem

SEEDS = [1, 2, 3, 4, 5]
ZDT_REFERENCE = [1.1, 1.1]
# (population, generations, reference point): evaluations = population x generations; the
# small budget is still far from the front (f2 up to ~3), so its reference point is looser
ZDT_BUDGETS = [
    (100, 100, [1.1, 1.1]),
    (20, 25, [1.1, 10.0]),
]
MIXED_REFERENCE = [1.1, 2.5]
MIXED_BUDGET = (20, 15)


def provenance(extra):
    return {
        "generator": "tools/optimize/pymoo_reference.py",
        "pymoo": pymoo.__version__,
        "numpy": np.__version__,
        "python": platform.python_version(),
        **extra,
    }


def hypervolume_sets():
    rng = np.random.default_rng(20261127)
    cases = []
    for n_obj, n_points in [(2, 5), (2, 40), (2, 200), (3, 10), (3, 60), (4, 20)]:
        points = rng.uniform(0.0, 1.2, size=(n_points, n_obj))
        reference = np.full(n_obj, 1.0)
        cases.append(
            {
                "reference": reference.tolist(),
                "points": points.tolist(),
                "hypervolume": float(HV(ref_point=reference)(points)),
            }
        )
    # a front on a curve (ZDT1's), all points inside
    f1 = np.linspace(0.0, 1.0, 25)
    front = np.column_stack([f1, 1.0 - np.sqrt(f1)])
    cases.append(
        {
            "reference": ZDT_REFERENCE,
            "points": front.tolist(),
            "hypervolume": float(HV(ref_point=np.array(ZDT_REFERENCE))(front)),
        }
    )
    return {
        "provenance": provenance(
            {"what": "pymoo.indicators.hv.HV on seeded uniform points in [0, 1.2]^k (seed 20261127) and 25 points of ZDT1's front"}
        ),
        "cases": cases,
    }


class Recorded(ElementwiseProblem):
    """A problem that records every objective vector it evaluates."""

    def __init__(self, inner, **kwargs):
        self.inner = inner
        self.seen = []
        super().__init__(**kwargs)

    def _evaluate(self, x, out, *args, **kwargs):
        f = self.inner(x)
        self.seen.append(f)
        out["F"] = f


def zdt_runs():
    results = []
    for name in ["zdt1", "zdt2", "zdt3"]:
        zdt = get_problem(name, n_var=30)
        for pop, gens, reference in ZDT_BUDGETS:
            runs = []
            for seed in SEEDS:
                problem = Recorded(
                    lambda x: zdt.evaluate(x[None, :])[0],
                    n_var=30,
                    n_obj=2,
                    xl=zdt.xl,
                    xu=zdt.xu,
                )
                start = time.perf_counter()
                res = minimize(problem, NSGA2(pop_size=pop), ("n_gen", gens), seed=seed)
                seconds = time.perf_counter() - start
                archive = np.array(problem.seen)
                hv = HV(ref_point=np.array(reference))
                runs.append(
                    {
                        "seed": seed,
                        "evaluations": len(archive),
                        "hypervolume_archive": float(hv(archive)),
                        "hypervolume_final": float(hv(res.F)),
                        "seconds": seconds,
                    }
                )
            results.append(
                {"problem": name, "population": pop, "generations": gens, "reference_point": reference, "runs": runs}
            )
    return {
        "provenance": provenance(
            {
                "what": "pymoo NSGA2(pop_size) with its defaults on get_problem(name, n_var=30), termination ('n_gen', generations), minimize(seed=seed)",
                "seeds": SEEDS,
            }
        ),
        "cases": results,
    }


def mixed_toy(x1, x2, k):
    """The mixed toy problem: ZDT1's shape with g(x2, k) = 1 + (x2 - 0.5)^2 + 0.25 (k - 2)^2,
    x1, x2 in [0, 1], k in {0, ..., 4}; the front is g = 1 (x2 = 0.5, k = 2)."""
    g = 1.0 + (x2 - 0.5) ** 2 + 0.25 * (k - 2) ** 2
    return np.array([x1, g * (1.0 - np.sqrt(x1 / g))])


class MixedToy(ElementwiseProblem):
    def __init__(self):
        self.seen = []
        variables = {"x1": Real(bounds=(0.0, 1.0)), "x2": Real(bounds=(0.0, 1.0)), "k": Integer(bounds=(0, 4))}
        super().__init__(vars=variables, n_obj=2)

    def _evaluate(self, x, out, *args, **kwargs):
        f = mixed_toy(x["x1"], x["x2"], x["k"])
        self.seen.append(f)
        out["F"] = f


def mixed_runs():
    pop, gens = MIXED_BUDGET
    runs = []
    for seed in SEEDS:
        problem = MixedToy()
        algorithm = MixedVariableGA(pop_size=pop, survival=RankAndCrowding())
        res = minimize(problem, algorithm, ("n_gen", gens), seed=seed)
        archive = np.array(problem.seen)
        hv = HV(ref_point=np.array(MIXED_REFERENCE))
        runs.append(
            {
                "seed": seed,
                "evaluations": len(archive),
                "hypervolume_archive": float(hv(archive)),
                "hypervolume_final": float(hv(res.F)),
            }
        )
    return {
        "provenance": provenance(
            {
                "what": "pymoo MixedVariableGA(pop_size, survival=RankAndCrowding()) on the mixed toy problem, termination ('n_gen', generations)",
                "problem": mixed_toy.__doc__.replace("\n    ", " "),
                "seeds": SEEDS,
            }
        ),
        "reference_point": MIXED_REFERENCE,
        "population": pop,
        "generations": gens,
        "runs": runs,
    }


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=Path("reference/optimize"))
    args = parser.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    for name, make in [
        ("hypervolume.json", hypervolume_sets),
        ("nsga2_mixed.json", mixed_runs),
        ("nsga2_zdt.json", zdt_runs),
    ]:
        data = make()
        (args.out / name).write_text(json.dumps(data, indent=1) + "\n")
        print(f"wrote {args.out / name}")


if __name__ == "__main__":
    main()
