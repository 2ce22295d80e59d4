"""bench/paper_cost.py (docs/performance.md, "Paper size: cost per figure") on answers known by
hand: the command parser on constructed make -n output (continuations, $((...)), branches that
inherit their grains, an incline start and branch), the grain-step and CPU-second sums of a tiny
constructed case, SIZE=test's make -n parsed into as many runs of each kind as the size file's
grids give (counted here from pipelines/sizes/test.mk, not from make), and exit code 2 with one
line for bad input."""
import argparse
import importlib.util
import os
import re
import subprocess
import sys
import tempfile
import unittest

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
SCRIPT = os.path.join(ROOT, "bench", "paper_cost.py")
_spec = importlib.util.spec_from_file_location("paper_cost", SCRIPT)
paper_cost = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(paper_cost)

COSTS = ["--frictionless", "0.5:1,0.7:100", "--friction", "0.7:3.6", "--equilibrium", "0.5:2",
         "--incline", "3:6", "--incline-friction", "10:20"]

# make -n output as the pipelines print it: a LAUNCH prefix, continuations, unexpanded shell
# arithmetic, a --frame -1 branch of a shear run, an equilibrium run, an incline start (its
# grains from --grains) with a run and a branch, an analysis reading comma-joined lists.
MADE = r"""mkdir -p R/
srun -n1 -c1 B/gf-pack --quiet --grains 100 \
  --packing-fraction 0.500 --seed 1 -o R/pack_nu0.500_s1.h5
B/gf-pack --quiet --grains 200 --packing-fraction 0.700 --seed 1 -o R/pack_nu0.700_s1.h5
B/gf-shear --quiet  -i R/pack_nu0.500_s1.h5 -o R/shear_a.h5 --rate 1e-02 \
  --restitution 0.00 --friction 0.00 \
  --seed 1 --strain 2 \
  --strain-step 0.0005 \
  --frame-every $((2 * 400))
B/gf-shear --quiet -i R/pack_nu0.700_s1.h5 -o R/shear_b.h5 --rate 1e-02 --restitution 0.92 --friction 0.40 --strain 3 --frame-every 100
B/gf-shear --quiet  -i R/shear_b.h5 --frame -1 -o R/window_b.h5 --rate -1e-02 --restitution 0.92 --friction 0.40 --steps 7 --frame-every 1
B/gf-shear --quiet --rate 0 --restitution 1 --friction 0 -i R/pack_nu0.500_s1.h5 -o R/eq.h5 --temperature 1 --dt 1e-4 --steps 50 --frame-every 10
B/gf-pack --quiet --incline --width 10 \
  --height 12 --grains 30 --seed 1 -o R/incline_pack.h5
B/gf-incline --quiet  -i R/incline_pack.h5 -o R/incline_th20.h5 --angle 20 \
  --restitution 0.50 --friction 0.00 \
  --time 20 --time-step 5e-3  \
  --frame-every 1000 --profile-block 200
B/gf-incline --quiet  -i R/incline_th20.h5 -o R/incline_branch.h5 --angle 30 \
  --restitution 0.50 --friction 0.40 --frame -1 \
  --time 10 --time-step 5e-3 \
   \
  --frame-every 1000 --profile-block 200
B/gf-correlate --quiet -o R/table.h5 --reference R/shear_a.h5,R/shear_b.h5 R/window_b.h5
B/gf-stz d2min --quiet --cutoff 2 -o R/d2.h5 -i R/shear_a.h5 --branch R/window_b.h5 --frames -1,10
/usr/bin/python3 pipelines/plot/x.py --from-strain 0.5 F/fig.png R/shear_a.h5
"""


def run(*args):
    return subprocess.run([sys.executable, SCRIPT, *args], capture_output=True, text=True)


def size_variables(path):
    """NAME := value lines of a size file, $(NAME) references substituted (enough for test.mk)."""
    values = {}
    with open(path) as f:
        for line in f:
            m = re.match(r"([A-Z0-9_.]+)\s*:=\s*(.*?)\s*(#.*)?$", line)
            if m:
                values[m.group(1)] = re.sub(r"\$\((\w+)\)", lambda r: values.get(r.group(1), ""), m.group(2))
    return {k: v.split() for k, v in values.items()}


class Parser(unittest.TestCase):
    def setUp(self):
        self.runs, self.analyses = paper_cost.parse_runs(MADE)

    def test_continuations_and_arithmetic(self):
        lines = paper_cost.logical_lines(MADE)
        shear = [line for line in lines if "-o R/shear_a.h5" in line][0]
        self.assertIn("--strain-step 0.0005", shear)
        self.assertTrue(shear.endswith("--frame-every 800"), shear)
        self.assertEqual(len([line for line in lines if "gf-" in line or "python3" in line]), 12)

    def test_runs(self):
        r = self.runs
        self.assertEqual(sorted(r), sorted(["R/pack_nu0.500_s1.h5", "R/pack_nu0.700_s1.h5", "R/shear_a.h5",
                                            "R/shear_b.h5", "R/window_b.h5", "R/eq.h5", "R/incline_pack.h5",
                                            "R/incline_th20.h5", "R/incline_branch.h5"]))
        # strain 2 at 5e-4: 4000 steps of the 100-grain packing at nu = 0.5.
        self.assertEqual((r["R/shear_a.h5"]["grains"], r["R/shear_a.h5"]["steps"], r["R/shear_a.h5"]["nu"]),
                         (100, 4000, 0.5))
        self.assertEqual(r["R/shear_a.h5"]["frames"], 1 + 4000 // 800)
        # strain 3 at the default step 1e-3; friction and restitution read.
        b = r["R/shear_b.h5"]
        self.assertEqual((b["grains"], b["steps"], b["mu"], b["e"], b["kind"]), (200, 3000, 0.4, 0.92, "shear"))
        # The branch inherits its parent's grains and nu; a negative rate is a value, not an option.
        w = r["R/window_b.h5"]
        self.assertEqual((w["grains"], w["steps"], w["nu"], w["rate"], w.get("branch")), (200, 7, 0.7, -0.01, True))
        self.assertEqual((r["R/eq.h5"]["kind"], r["R/eq.h5"]["steps"]), ("equilibrium", 50))
        # Incline: 20 tau at 5e-3 = 4000 steps, 10 tau = 2000 for the branch, 30 grains from --grains.
        self.assertEqual((r["R/incline_th20.h5"]["grains"], r["R/incline_th20.h5"]["steps"]), (30, 4000))
        ib = r["R/incline_branch.h5"]
        self.assertEqual((ib["grains"], ib["steps"], ib["mu"], ib["branch"]), (30, 2000, 0.4, True))
        self.assertEqual([(a["program"], a["sub"]) for a in self.analyses],
                         [("gf-correlate", None), ("gf-stz", "d2min"), ("python", "x.py")])
        # "--frames -1,10" is a value (negative), not an option.
        self.assertEqual(self.analyses[1]["options"]["--frames"], "-1,10")

    def test_incline_start_without_grains(self):
        # lib/packing/incline.cpp's count: 0.8 * 100 * 50 / (pi/4 * (1 + 0.26^2/3)) = 4981;
        # a counted start overrides it.
        opts = {"--incline": True, "--width": "100", "--height": "50"}
        self.assertEqual(paper_cost.incline_pack_grains(opts), 4981)
        self.assertEqual(paper_cost.incline_pack_grains(opts, {(100.0, 50.0): 5036}), 5036)

    def test_figure_targets_need_not_be_last(self):
        self.assertEqual(paper_cost.figure_targets(MADE, "F"), ["F/fig.png"])

    def test_unknown_parent_is_an_error(self):
        with self.assertRaises(paper_cost.CostError):
            paper_cost.parse_runs("B/gf-shear -i R/none.h5 -o R/x.h5 --steps 3\n")


class Sums(unittest.TestCase):
    def test_grain_steps_and_seconds(self):
        runs, analyses = paper_cost.parse_runs(MADE)
        args = argparse.Namespace(
            frictionless=["0.5:1,0.7:100", "0.92=0.5:2"], friction="0.7:3.6", equilibrium="0.5:2",
            incline="3:6", incline_friction="10:20", pack_us_per_grain=0.0, incline_pack_seconds=0.0,
            analysis_ms="gf-correlate:1000,gf-stz d2min:500", incline_grains="")
        costs = paper_cost.Costs(args)
        grain_steps, sim, ana = paper_cost.cost_of(runs, analyses, costs, runs)
        # 100*4000 + 200*3000 + 200*7 + 100*50 + 30*4000 + 30*2000
        self.assertEqual(grain_steps, 400000 + 600000 + 1400 + 5000 + 120000 + 60000)
        # shear_a (e = 0): 4e5 grain-steps at 1 us; shear_b and its branch: 3.6 s per
        # strain at 1e-3 per step and 1e4 grains = 3.6e-7 s per grain-step; eq: 5000 at 2 us;
        # incline 1.2e5 at 3..6 us; branch 6e4 at 10..20 us.
        low = 0.4 + (600000 + 1400) * 3.6e-7 + 0.01 + 0.36 + 0.6
        high = 0.4 + (600000 + 1400) * 3.6e-7 + 0.01 + 0.72 + 1.2
        self.assertAlmostEqual(sim[0], low, places=9)
        self.assertAlmostEqual(sim[1], high, places=9)
        # gf-correlate reads shear_a (6 frames), shear_b (31) and window_b (8), at 1 s per frame of
        # 10^4 grains: (6 * 100 + 31 * 200 + 8 * 200) / 1e4 s; gf-stz d2min the two frames it names
        # of the 100-grain run, at 0.5 s per frame of 10^4 grains.
        self.assertAlmostEqual(ana, (6 * 100 + 31 * 200 + 8 * 200) / 1e4 + 2 * 100 / 1e4 * 0.5, places=12)

    def test_restitution_tables(self):
        args = argparse.Namespace(
            frictionless=["0.5:1,0.7:100", "0.92=0.5:2,0.7:8"], friction="0.7:1", equilibrium="0.5:1",
            incline="1:1", incline_friction="1:1", pack_us_per_grain=0.0, incline_pack_seconds=0.0,
            analysis_ms="", incline_grains="")
        costs = paper_cost.Costs(args)
        # A measured e: its table (log-linear in nu: sqrt(1 * 100) = 10 at 0.6); between two: both
        # tables' costs as the range; flat outside the measured nu.
        for nu, e, expected in ((0.5, 0.0, (1, 1)), (0.6, 0.0, (10, 10)), (0.7, 0.92, (8, 8)),
                                (0.7, 0.5, (8, 100)), (0.3, 0.25, (1, 2)), (0.5, 1.0, (2, 2))):
            got = costs.frictionless_us(nu, e)
            self.assertAlmostEqual(got[0], expected[0], places=10, msg=(nu, e))
            self.assertAlmostEqual(got[1], expected[1], places=10, msg=(nu, e))

    def test_interpolation_is_paper_estimates(self):
        self.assertEqual(paper_cost.paper_estimate.cost_at.__module__, "paper_estimate")
        self.assertAlmostEqual(paper_cost.paper_estimate.cost_at({0.5: 1.0, 0.7: 100.0}, 0.6), 10.0, places=12)


class TestSize(unittest.TestCase):
    def test_runs_of_the_test_size(self):
        v = size_variables(os.path.join(ROOT, "pipelines", "sizes", "test.mk"))
        with tempfile.TemporaryDirectory() as tmp:
            runs, _ = paper_cost.parse_runs(paper_cost.make_dry_run(ROOT, "test", "paper-files", tmp))
        # Shear runs from packings, by name (nu, e, mu, rate): chapter 4's sweep and Bagnold pair,
        # chapter 5's grids and reference, the STZ fit's grids (chapter 6), then the half-step runs.
        rate = v["CH4_RATE"][0]
        shear = {(nu, e, "0.00", rate) for e in v["CH4_E"] for nu in v["CH4_NU"]}
        shear |= {(nu, v["CH4_FRICTION_E"][0], "0.40", rate) for nu in v["CH4_FRICTION_NU"]}
        shear |= {(v["CH4_BAGNOLD_NU"][0], "0.00", "0.00", r) for r in v["CH4_BAGNOLD_RATES"]}
        shear |= {(nu, e, "0.00", rate) for e in v["CH5_E"] for nu in v["CH5_NU"]}
        shear |= {(nu, v["CH5_FRICTION_E"][0], mu, rate) for mu in v["CH5_MU"] for nu in v["CH5_FRICTION_NU"]}
        shear |= {(v["CH5_REFERENCE_NU"][0], v["CH5_REFERENCE_E"][0], "0.00", rate)}
        shear |= {(nu, e, "0.00", rate) for e in v["CH6_STZ_FIT_E"] for nu in v["CH6_STZ_FIT_NU"]}
        shear |= {(nu, v["CH5_FRICTION_E"][0], "0.40", rate) for nu in v["CH6_STZ_FRICTION_NU"]}
        halfstep = [(nu, e) for e in v["CH6_HALFSTEP_E"] for nu in v["CH6_HALFSTEP_NU"]]
        kinds = paper_cost.by_kind(runs)
        frictional = {s for s in shear if s[2] != "0.00"}
        self.assertEqual(len(kinds["shear runs"]), len(shear) - len(frictional) + len(halfstep))
        self.assertEqual(len(kinds["shear runs (μ > 0)"]), len(frictional))
        # Branches: Fig 5.1's windows and Fig 6.9's two D2min branches.
        self.assertEqual(len(kinds["shear branches"]), len(v["CH5_CLUSTER_E"]) + 2)
        self.assertEqual(len(kinds["equilibrium runs"]), 3 * len(v["CH6_EQ_NU"]))
        packings = {nu for nu, *_ in shear} | set(v["PACK_NU"]) | set(v["CH6_EQ_NU"])
        self.assertEqual(len(kinds["packings"]), len(packings) + len(v["PACK_SEEDS"][1:]) * len(v["PACK_NU"]))
        incline = {(a, v["INCLINE_E"][0]) for a in v["INCLINE_ANGLES_MU0"] + v["INCLINE_CRITICAL_ANGLES"]}
        incline |= {(a, v["CH6_INCLINE_E"][0]) for a in v["CH6_INCLINE_ANGLES_MU0"]}
        self.assertEqual(len(kinds["incline runs"]), len(incline))
        self.assertEqual(len(kinds["incline branches (μ > 0)"]),
                         len(v["INCLINE_ANGLES_MU04"]) + len(v["CH6_INCLINE_ANGLES_MU04"]))
        # Steps: SHEAR_STRAIN / SHEAR_STRAIN_STEP, SHEAR_LONG_STRAIN at SHEAR_LONG_NU, twice as many
        # for a half-step run; every grain count PACK_GRAINS.
        step = float(v["SHEAR_STRAIN_STEP"][0])

        def steps(nu):
            return round(float(v["SHEAR_LONG_STRAIN" if nu in v["SHEAR_LONG_NU"] else "SHEAR_STRAIN"][0]) / step)
        expected = sum(steps(nu) for nu, *_ in shear) + sum(2 * steps(nu) for nu, _ in halfstep)
        got = sum(r["steps"] for k in ("shear runs", "shear runs (μ > 0)") for r in kinds[k])
        self.assertEqual(got, expected)
        self.assertEqual({r["grains"] for k in ("shear runs", "packings") for r in kinds[k]},
                         {int(v["PACK_GRAINS"][0])})
        inc_steps = round(float(v["INCLINE_TIME"][0]) / float(v["INCLINE_TIME_STEP"][0]))
        self.assertEqual({r["steps"] for r in kinds["incline runs"]}, {inc_steps})

    def test_whole_report_runs(self):
        out = run("--size", "test", *COSTS)
        self.assertEqual(out.returncode, 0, out.stderr)
        self.assertIn("| **paper-files** (each run once) |", out.stdout)
        self.assertIn("| figures/fig4_2.png |", out.stdout)


class BadInput(unittest.TestCase):
    def check(self, *args):
        out = run(*args)
        self.assertEqual(out.returncode, 2, out.stderr)
        self.assertEqual(out.stdout, "")
        self.assertEqual(len(out.stderr.strip().splitlines()), 1, out.stderr)
        return out.stderr

    def test_missing_makefile(self):
        with tempfile.TemporaryDirectory() as tmp:
            self.assertIn("Makefile.sweeps", self.check("--repo", tmp, *COSTS))

    def test_bad_cost_pairs(self):
        bad = list(COSTS)
        bad[1] = "0.5"
        self.assertIn("--frictionless", self.check(*bad))
        bad[1] = "x=0.5:1"
        self.assertIn("--frictionless", self.check(*bad))
        bad = list(COSTS)
        bad[3] = "0.7:-1"
        self.assertIn("not positive", self.check(*bad))
        bad = list(COSTS)
        bad[7] = "6:3"
        self.assertIn("--incline", self.check(*bad))


if __name__ == "__main__":
    unittest.main()
