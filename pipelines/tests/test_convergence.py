"""convergence.py: the classes on constructed series with known answers, the convergence
study's make target end to end on a tiny grid (and its refusal of a grid with one step), and the
study's committed CSV files against each other."""
import csv
import math
import os
import tempfile
import unittest

import numpy as np

import study_make  # a sibling module: the step studies' make runner
from analysis import convergence

STEPS = np.array([2e-3, 1e-3, 5e-4, 2.5e-4, 1.25e-4])


def noisy(values, relative, seed):
    rng = np.random.default_rng(seed)
    errors = relative * np.abs(values)
    return values + errors * rng.standard_normal(len(values)), errors


class ClassifyTest(unittest.TestCase):
    def test_chi2_probability_known_quantiles(self):
        for chi2, dof, p in ((3.841, 1, 0.05), (9.210, 2, 0.01), (7.815, 3, 0.05), (11.070, 5, 0.05), (2.0, 4, 0.7358)):
            self.assertAlmostEqual(convergence.chi2_probability(chi2, dof), p, delta=2e-4)

    def test_flat_series_is_converged(self):
        q, s = noisy(np.full(5, 0.29), 0.003, 1)
        c = convergence.classify(STEPS, q, s, 1e-3)
        self.assertEqual(c["class"], "converged")
        self.assertEqual(c["steps"], 5)
        self.assertAlmostEqual(c["span"], 16.0)

    def test_linear_approach_gives_its_limit(self):
        # Q = 2 + 300 h: 0.26 (13 %) between the default and the finest step, limit 2.
        q = 2 + 300 * STEPS
        c = convergence.classify(STEPS, q, np.full(5, 1e-3), 1e-3)
        self.assertEqual(c["class"], "converging")
        self.assertAlmostEqual(c["limit"], 2.0, delta=3 * c["limit_error"] + 1e-3)
        self.assertAlmostEqual(c["limit_exponent"], 1.0, delta=0.05)
        # 1 % of 2 is 0.02 = 300 h: h = 6.7e-5.
        self.assertAlmostEqual(c["step_1pct"], 0.02 / 300, delta=0.1 * 0.02 / 300)

    def test_square_root_approach_from_below(self):
        q = -1.5 - 20 * np.sqrt(STEPS)
        q, s = noisy(q, 1e-4, 2)
        c = convergence.classify(STEPS, q, s, 1e-3)
        self.assertEqual(c["class"], "converging")
        self.assertLess(abs(c["limit"] + 1.5), 3 * c["limit_error"] + 1e-3)
        self.assertAlmostEqual(c["limit_exponent"], 0.5, delta=0.1)

    def test_pure_power_is_regularisation_dependent(self):
        # z ∝ h^0.45 with 2 % errors: no limit told from 0 over a factor of 16.
        q, s = noisy(40 * STEPS**0.45, 0.02, 3)
        c = convergence.classify(STEPS, q, s, 1e-3)
        self.assertEqual(c["class"], "regularisation-dependent")
        self.assertAlmostEqual(c["exponent"], 0.45, delta=3 * c["exponent_error"])
        self.assertLess(c["exponent_error"], 0.1)

    def test_extrapolation_through_zero_is_not_a_limit(self):
        # A count falling towards 0 faster than linearly: Q0 + b h^α extrapolates below 0.
        q, s = noisy(0.186 + 0.42 * (STEPS / 1.25e-4 - 1) ** 0.8 / 15**0.8 * 4, 0.01, 4)
        c = convergence.classify(STEPS, q, s, 1e-3)
        self.assertNotEqual(c["class"], "converging")
        q, s = noisy(1.4 * STEPS**0.55, 0.02, 5)
        c = convergence.classify(STEPS, q, s, 1e-3)
        self.assertEqual(c["class"], "regularisation-dependent")

    def test_errors_too_large_to_show_convergence(self):
        q = np.array([4.6, 99.0, 12.8, 9.5, 4.3])
        s = np.array([0.2, 107.0, 2.7, 2.3, 0.35])
        c = convergence.classify(STEPS, q, s, 1e-3)
        self.assertNotEqual(c["class"], "converged")

    def test_curved_fall_without_limit_is_regularisation_dependent(self):
        # z over force-bearing contacts at ν = 0.80, e = 0.5: falling ever faster, no power fits.
        steps = np.append(STEPS, 6.25e-5)
        q = np.array([0.858, 0.6087, 0.4293, 0.2939, 0.1860, 0.1097])
        s = np.array([0.012, 0.0092, 0.0084, 0.0076, 0.0054, 0.0038])
        c = convergence.classify(steps, q, s, 1e-3)
        self.assertEqual(c["class"], "regularisation-dependent")
        self.assertAlmostEqual(c["exponent_finest"], math.log(0.1097 / 0.1860) / math.log(0.5), places=12)
        self.assertIn("local exponent 0.76", convergence.class_text(c))

    def test_pure_power_over_a_short_span_is_unsettled(self):
        steps = STEPS[:3]  # a factor of 4 only
        q, s = noisy(40 * steps**0.45, 0.02, 3)
        c = convergence.classify(steps, q, s, 1e-3)
        self.assertEqual(c["class"], "unsettled")

    def test_two_steps_apart_are_unsettled(self):
        c = convergence.classify([1e-3, 5e-4], [1.0, 1.2], [0.01, 0.01], 1e-3)
        self.assertEqual(c["class"], "unsettled")
        self.assertEqual(convergence.class_text(c), "unsettled (too few steps)")

    def test_one_percent_rule_without_errors(self):
        c = convergence.classify([1e-3, 5e-4, 2.5e-4], [1.009, 1.004, 1.0], [math.nan] * 3, 1e-3)
        self.assertEqual(c["class"], "converged")
        c = convergence.classify([1e-3, 5e-4, 2.5e-4], [1.02, 1.01, 1.0], [math.nan] * 3, 1e-3)
        self.assertNotEqual(c["class"], "converged")

    def test_scatter_beyond_the_errors_is_not_a_fit(self):
        q = np.array([1.0, 1.3, 0.9, 1.4, 0.8])
        c = convergence.classify(STEPS, q, np.full(5, 0.01), 1e-3)
        self.assertEqual(c["class"], "unsettled")
        self.assertTrue(math.isnan(c["limit"]))

    def test_nan_values_are_left_out(self):
        q = 2 + 300 * STEPS
        q[1] = math.nan
        c = convergence.classify(STEPS, q, np.full(5, 1e-3), 1e-3)
        self.assertEqual(c["steps"], 4)
        self.assertTrue(math.isnan(c["default_value"]))


class RowStatisticsTest(unittest.TestCase):
    def test_mean_of_ratios_against_ratio_of_means(self):
        import h5py

        # p alternates 1, 3 and s is 0.6: ⟨s⟩/⟨p⟩ = 0.3, ⟨s/p⟩ = (0.6 + 0.2)/2 = 0.4, std(p)/⟨p⟩ = 0.5;
        # the rows before strain 1 (p = 100) are left out.
        n = 400
        strain = np.concatenate([np.linspace(0, 0.9, 10), 1 + np.arange(n) * 0.01])
        p = np.concatenate([np.full(10, 100.0), np.tile([1.0, 3.0], n // 2)])
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "run.h5")
            with h5py.File(path, "w") as f:
                for name, values in (("strain", strain), ("pressure", p), ("shear_stress", np.full(len(p), 0.6))):
                    f.create_dataset(f"observables/{name}/value", data=values)
            (ratio, ratio_error), (cv, _) = convergence.row_statistics(path, 1.0)
        self.assertAlmostEqual(ratio, 0.4, places=12)
        self.assertAlmostEqual(cv, 0.5, places=12)
        self.assertLess(ratio_error, 1e-3)


class ActivationTest(unittest.TestCase):
    """Runs of two contact activations are not one series: read_rows refuses them."""

    def write_run(self, path, activation):
        import h5py

        with h5py.File(path, "w") as f:
            a = f.create_group("parameters").attrs
            a.update({"grains": 64, "packing_fraction": 0.8, "restitution": 0.5, "friction": 0.0,
                      "tolerance": 1e-10, "rate": 1.0, "dt": 1e-3})
            if activation is not None:
                a["activation"] = activation

    def write_table(self, path, run):
        import h5py

        with h5py.File(path, "w") as f:
            f.create_group("parameters").attrs["program"] = "gf-kinetic"
            f.create_group("runs").create_dataset("input", data=np.array([run], dtype=object),
                                                  dtype=h5py.string_dtype())

    def test_mixed_activations_are_refused(self):
        with tempfile.TemporaryDirectory() as d:
            for name, activation in (("old", None), ("gap", "predicted-gap"), ("overlap", "overlap")):
                self.write_run(f"{d}/{name}.h5", activation)
                self.write_table(f"{d}/t_{name}.h5", f"{d}/{name}.h5")
            # A run made before the option is a predicted-gap run.
            rows, activation, _ = convergence.read_rows([f"{d}/t_old.h5", f"{d}/t_gap.h5"])
            self.assertEqual(activation, "predicted-gap")
            rows, activation, _ = convergence.read_rows([f"{d}/t_overlap.h5"])
            self.assertEqual(activation, "overlap")
            with self.assertRaisesRegex(ValueError, "mix contact activations"):
                convergence.read_rows([f"{d}/t_gap.h5", f"{d}/t_overlap.h5"])


GRID = """CONV_POINTS       := 0.700:0.50:0.00
CONV_REFERENCE    := 0.500:0.92:0.00
CONV_STEPS        := {steps}
CONV_DEFAULT_STEP := 1e-3
CONV_GRAINS       := 64
CONV_FINE_POINTS  :=
CONV_FINE_STEPS   :=
CONV_LARGE_GRAINS :=
CONV_LARGE_POINTS :=
CONV_LARGE_STEPS  :=
CONV_TOLERANCE         := 1e-10
CONV_TOLERANCE_POINT   := 0.700:0.50:0.00
CONV_TOLERANCE_STEP    := 1e-3
CONV_OTHER_TOLERANCES  := 1e-8
CONV_STRAIN        := 0.3
CONV_RATE          := 1
CONV_SEED          := 1
CONV_FROM_STRAIN   := 0.05
CONV_OBSERVE_STRAIN := 2e-3
CONV_FRAME_STRAIN  := 2e-3
CONV_CONTACT_GAPS  := 1e-3
CONV_D2MIN_STRAINS := 0.1 0.2
CONV_D2MIN_CUTOFF  := 2
"""


@unittest.skipUnless(study_make.HAVE_PROGRAMS, study_make.SKIP_REASON)
class ConvergenceMakeTest(unittest.TestCase):
    """make convergence-files on a 64-grain grid: two points, three steps, one more tolerance."""

    def make(self, d, steps, *extra):
        return study_make.run(d, GRID.format(steps=steps), ("CONVERGENCE",),
                              ("gf-pack", "gf-shear", "gf-correlate", "gf-network", "gf-kinetic", "gf-stz"), "convergence-files",
                              *extra)

    def test_tiny_study(self):
        import h5py

        with tempfile.TemporaryDirectory() as d:
            res = self.make(d, "2e-3 1e-3 5e-4")
            self.assertEqual(res.returncode, 0, res.stdout + res.stderr)
            with h5py.File(f"{d}/runs/convergence.h5", "r") as f:
                steps = f["series/step"][()]
                tol = f["series/tolerance"][()]
                nu = f["series/packing_fraction"][()]
                obs = [o.decode() if isinstance(o, bytes) else o for o in f["series/observable"][()]]
                self.assertEqual(sorted(set(np.round(steps, 12))), [5e-4, 1e-3, 2e-3])
                # The extra tolerance is a series of its own at one step.
                self.assertEqual(sorted(set(steps[tol == 1e-8])), [1e-3])
                self.assertEqual(sorted(set(np.round(nu, 3))), [0.5, 0.7])
                for key in ("p", "s_over_p", "s_over_p_rows", "p_cv", "z", "xi", "xi_length_ratio", "p_bc", "C_v", "z@0.001", "Phi@0.001",
                            "pf_mode", "d2min_black", "d2min_jaccard"):
                    self.assertIn(key, obs)
                classes = [c.decode() if isinstance(c, bytes) else c for c in f["classes/class"][()]]
                self.assertTrue(set(classes) <= {"converged", "converging", "regularisation-dependent", "unsettled"})
                cobs = [o.decode() if isinstance(o, bytes) else o for o in f["classes/observable"][()]]
                self.assertIn("xi_el", [o for o, n in zip(cobs, f["classes/packing_fraction"][()]) if n == 0.5])
                # The default step's value in the classes is the series' own.
                k = cobs.index("s_over_p")
                row = (np.isclose(nu, f["classes/packing_fraction"][k])) & (steps == 1e-3) & (tol == 1e-10)
                sp = [v for v, o in zip(f["series/value"][()][row], np.array(obs)[row]) if o == "s_over_p"]
                self.assertEqual(sp, [f["classes/default_value"][k]])
                # The series CSV holds /series row for row, in its units, to 6 significant digits.
                series = read_csv(f"{d}/runs/convergence_series.csv")
                self.assertEqual(len(series), len(steps))
                units = [u.decode() if isinstance(u, bytes) else u for u in f["series/unit"][()]]
                got = {(r["packing_fraction"], r["tolerance"], r["step"], r["observable"]): r for r in series}
                for i in range(len(steps)):
                    r = got[(f"{nu[i]:.3f}", f"{tol[i]:g}", f"{steps[i]:g}", obs[i])]
                    self.assertEqual(r["unit"], units[i])
                    value = f["series/value"][i]
                    if np.isfinite(value):
                        self.assertAlmostEqual(float(r["value"]), value, delta=1e-5 * abs(value))
                    else:
                        self.assertEqual(r["value"], "")
            with open(f"{d}/runs/convergence.md") as fh:
                md = fh.read()
            self.assertIn("### ν = 0.700, e = 0.50, μ = 0.00, N = 64, tolerance 1e-10", md)
            self.assertIn("### ν = 0.700, e = 0.50, μ = 0.00, N = 64, tolerance 1e-08", md)
            self.assertIn("γ̇dt = 0.001 (default)", md)
            self.assertIn("| z (age ≥ 2), gap 0.001σ |", md)
            self.assertIn("| D²min: black fraction |", md)
            # The D²min maps are gone once their statistics are written.
            self.assertEqual([n for n in os.listdir(f"{d}/runs") if n.endswith(".maps")], [])
            with open(f"{d}/figures/fig4_2_step.png", "rb") as fh:
                self.assertEqual(fh.read(8), b"\x89PNG\r\n\x1a\n")
            # Nothing left to do.
            q = self.make(d, "2e-3 1e-3 5e-4", "-q")
            self.assertEqual(q.returncode, 0, q.stdout + q.stderr)

    def test_grid_with_one_step_is_refused(self):
        with tempfile.TemporaryDirectory() as d:
            study_make.assert_refused(self, self.make(d, "1e-3"), d, "CONV_STEPS needs at least two strain steps")

    def test_default_step_outside_the_grid_is_refused(self):
        with tempfile.TemporaryDirectory() as d:
            study_make.assert_refused(self, self.make(d, "2e-3 5e-4"), d, "CONV_DEFAULT_STEP")


def read_csv(path):
    """The rows of a convergence.py CSV file (after its comment line) as dicts."""
    with open(path, newline="") as fh:
        lines = [line for line in fh if not line.startswith("#")]
    return list(csv.DictReader(lines))


class CommittedFilesTest(unittest.TestCase):
    """docs/results' two CSV files come from one convergence.py run: each class's default value and
    error are the series' at the default step, tolerance 1e-10, for the same point and N."""

    def test_classes_match_the_series(self):
        results = os.path.join(os.path.dirname(__file__), "..", "..", "docs", "results")
        classes = read_csv(os.path.join(results, "convergence_classes.csv"))
        series = read_csv(os.path.join(results, "convergence_series.csv"))
        with open(os.path.join(results, "convergence_classes.csv")) as fh:
            default = fh.readline().split("default step ")[1].split(",")[0]
        at_default = {(r["packing_fraction"], r["restitution"], r["friction"], r["grains"], r["observable"]): r
                      for r in series if r["step"] == default and r["tolerance"] == "1e-10"}
        self.assertGreater(len(classes), 100)
        for c in classes:
            key = (c["packing_fraction"], c["restitution"], c["friction"], c["grains"], c["observable"])
            self.assertIn(key, at_default, "class without a series value at the default step")
            for column in ("value", "error"):
                theirs, ours = at_default[key][column], c["default_" + column]
                if theirs == "" or ours in ("nan", "inf", "-inf"):
                    self.assertTrue(theirs == "" and ours in ("nan", "inf", "-inf"), (key, column, theirs, ours))
                else:
                    self.assertAlmostEqual(float(theirs), float(ours), delta=1e-5 * abs(float(ours)) + 1e-300,
                                           msg=(key, column))


if __name__ == "__main__":
    unittest.main()
