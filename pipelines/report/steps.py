"""Each section's step dependence: how the convergence study (pipelines/analysis/convergence.py
--classes-csv) classes the observables a section's comparisons use."""
import csv
import math

# The convergence study's observables (pipelines/analysis/convergence.py keys) each section's
# comparisons use; sections absent here use none the study classes.
SECTION_OBSERVABLES = {
    "ch4": ("p", "s_over_p", "T", "p_s", "p_k"),
    "ch5": ("xi_abs", "xi_abs_ratio", "a0", "theta0", "pf_mode", "pf_zero"),
    "ch5_jamming": ("p",),
    "ch6_kinetic": ("p_s", "p_bc", "T", "C_v", "omega"),
    "ch6_network": ("z", "z@0.01", "Phi", "Phi@0.01", "Psi", "Psi@0.01", "a_c", "lhs_627", "rhs_627", "xi_abs_ratio"),
    "ch6_stz": ("s_over_p", "p", "xi_abs_ratio"),
    "ch6_d2min": ("d2min_black", "d2min_median", "d2min_largest", "d2min_jaccard"),
}
NOT_STUDIED = {
    "incline": "the incline's observables are classed against its time step by `make incline-step` "
    "(docs/results/convergence.md), not in the classes file",
}
NEAR_LIMIT = 0.02
CLASSES = ("converged", "converging", "regularisation-dependent", "unsettled")


def read_step_classes(path):
    """The rows of convergence.py --classes-csv (its comment line first)."""
    with open(path, newline="") as fh:
        header = fh.readline().lstrip("# ").strip()
        return header, list(csv.DictReader(fh))


def near_limit(row):
    """Whether a converging observable's value at the default step lies within NEAR_LIMIT of its
    limit, or within their combined errors."""
    value, error = float(row["default_value"]), float(row["default_error"])
    limit, limit_error = float(row["limit"]), float(row["limit_error"])
    sigma = math.hypot(error if math.isfinite(error) else 0.0, limit_error if math.isfinite(limit_error) else 0.0)
    return abs(value - limit) <= max(NEAR_LIMIT * abs(limit), sigma)


def class_counts(rows, key):
    """For one observable: its label, how many state points class it each way, and at how many of
    the converging ones the default step is near the limit (None: the study has no such row)."""
    mine = [r for r in rows if r["observable"] == key]
    if not mine:
        return None
    count = {c: sum(r["class"] == c for r in mine) for c in CLASSES}
    near = sum(near_limit(r) for r in mine if r["class"] == "converging")
    return mine[0]["label"], count, near


def step_note(step_classes, section, path):
    """One paragraph: per observable the section uses, how many of the study's state points
    class it converged, converging (and at how many the default step is within NEAR_LIMIT, or
    the errors, of the limit), regularisation-dependent or unsettled."""
    if step_classes is None:
        return []
    if section in NOT_STUDIED:
        return ["", f"**Step dependence**: {NOT_STUDIED[section]}.", ""]
    header, rows = step_classes
    parts = []
    for key in SECTION_OBSERVABLES.get(section, ()):
        counted = class_counts(rows, key)
        if counted is None:
            continue
        label, count, near = counted
        words = []
        for c, n in count.items():
            if not n:
                continue
            words.append(f"{c} {n}")
            if c == "converging":
                words[-1] += f" (at {near} of them the default step within {NEAR_LIMIT * 100:g} % of the limit or its errors)"
        parts.append(f"{label}: " + ", ".join(words))
    if not parts:
        return []
    points = len({(r["packing_fraction"], r["restitution"], r["friction"]) for r in rows})
    return [
        "",
        f"**Step dependence** of the quantities above over the convergence study's {points} "
        f"state points (`{path}`: {header}; classes and tables in docs/results/convergence.md): " + "; ".join(parts) + ".",
        "",
    ]
