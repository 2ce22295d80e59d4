#!/usr/bin/env python3
"""Does a frictional step left at the sweep cap have a solution at all?

Reads the files that dump_capped_steps.patch writes (one per step: the bodies, and every row's
grains, normal, bounds b_n and b_t, 1/W_nn and impulses) and answers two linear programs per
step (HiGHS, through SciPy), on the self-stresses of its rows: impulses with no net impulse or
torque on any grain, 0 <= P_n <= 1.

  work0   the work -(P_n b_n), per unit of its sum P_n, of the self-stress without friction
          (P_t = 0) that does the least work; 0 when none does negative work. Then (Farkas)
          impulses can meet every normal constraint u_n >= b_n, the step is no rigid jam,
          and the frictionless problem of the same rows has a solution (its matrix is positive
          semi-definite). A negative value is the normal constraints' shortfall: they can be
          met within -work0 at best.
  work    the same within the Coulomb cones (|P_t| <= mu P_n), work -(P_n b_n + P_t b_t); 0
          when none does negative work. Then the step's linear complementarity problem (the
          region solves' form, docs/method/solver.md) has a solution: its matrix is copositive
          (Anitescu & Potra 1997) and every solution of the homogeneous problem is such a
          self-stress, so Cottle, Pang & Stone's theorem 3.8.6 applies. A negative value
          leaves existence open: a solution must then slide at contacts of that self-stress.

A self-stress moves no grain, so neither answer depends on the velocities or the impulses the
step holds: only on the rows' geometry and bounds. Needs python3-numpy and python3-scipy.
"""
import argparse
import sys

import numpy as np

try:
    import scipy.sparse as sp
    from scipy.optimize import linprog
except ImportError:
    sys.exit("capped_steps.py: needs SciPy (apt-get install python3-scipy)")


def load(name):
    """mu, Υ, the residual at the cap, the number of bodies, and the rows (i, j, n_x, n_y, b_n, b_t,
    1/W_nn, P_n, P_t)."""
    with open(name) as f:
        head = f.readline().split()
        if head[:2] != ["#", "mu"]:
            raise ValueError(f"{name}: not a dump of dump_capped_steps.patch")
        mu, upsilon, residual = float(head[2]), float(head[4]), float(head[6])
        bodies, rows = 0, []
        for line in f:
            kind, *values = line.split()
            if kind == "B":
                bodies += 1
            elif kind == "R":
                rows.append([float(v) for v in values])
            else:
                raise ValueError(f"{name}: unknown line kind {kind!r}")
    return mu, upsilon, residual, bodies, np.array(rows)


def impulse_map(rows, n_bodies):
    """H: the net impulse (x, y) and R-scaled torque on each grain of unit P_n and P_t per row
    (columns 2c and 2c + 1): +P on i, −P on j, torque −2P_t on both (I = mR²/2)."""
    i, j = rows[:, 0].astype(int), rows[:, 1].astype(int)
    nx, ny = rows[:, 2], rows[:, 3]
    pn, pt = 2 * np.arange(len(rows)), 2 * np.arange(len(rows)) + 1
    r, c, v = [], [], []
    for body, s in ((i, 1.0), (j, -1.0)):
        r += [3 * body, 3 * body + 1, 3 * body, 3 * body + 1, 3 * body + 2]
        c += [pn, pn, pt, pt, pt]
        v += [s * nx, s * ny, -s * ny, s * nx, -2.0 + 0 * nx]
    return sp.csr_matrix((np.concatenate(v), (np.concatenate(r), np.concatenate(c))),
                         shape=(3 * n_bodies, 2 * len(rows)))


def cone(mu, n_rows):
    """|P_t| <= mu P_n as two rows per contact (P_t - mu P_n <= 0, -P_t - mu P_n <= 0)."""
    k = np.arange(n_rows)
    r = np.concatenate([2 * k, 2 * k, 2 * k + 1, 2 * k + 1])
    c = np.concatenate([2 * k + 1, 2 * k, 2 * k + 1, 2 * k])
    v = np.concatenate([np.ones(n_rows), -mu * np.ones(n_rows), -np.ones(n_rows), -mu * np.ones(n_rows)])
    return sp.csr_matrix((v, (r, c)), shape=(2 * n_rows, 2 * n_rows))


def least_work(rows, H, mu, friction):
    """The least work of a self-stress per unit of its sum P_n (a velocity; 0 if none does negative
    work) and the number of rows it loads."""
    n_rows = len(rows)
    scale = max(np.abs(rows[:, 4:6]).max(), 1e-300)
    cost = np.empty(2 * n_rows)
    cost[0::2], cost[1::2] = -rows[:, 4] / scale, -rows[:, 5] / scale
    used = np.flatnonzero(np.diff(H.indptr))  # grains some row acts on
    lp = linprog(cost, A_ub=cone(mu, n_rows), b_ub=np.zeros(2 * n_rows), A_eq=H[used],
                 b_eq=np.zeros(len(used)), bounds=[(0, 1), (None, None) if friction else (0, 0)] * n_rows,
                 method="highs")
    if lp.status != 0:
        return float("nan"), 0
    total = lp.x[0::2].sum()
    return (lp.fun / total * scale if total > 0 else 0.0), int((lp.x[0::2] > 1e-9).sum())


def analyse(name):
    mu, upsilon, residual, bodies, rows = load(name)
    H = impulse_map(rows, bodies)
    work, used = least_work(rows, H, mu, True)
    work0, _ = least_work(rows, H, mu, False)
    return dict(rows=len(rows), bearing=int((rows[:, 7] > 0).sum()), residual=residual / upsilon,
                work0=work0 / upsilon, work=work / upsilon, self_stress_rows=used)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("steps", nargs="+", help="step files written by dump_capped_steps.patch")
    args = parser.parse_args()
    print("step rows bearing residual/Υ work0/Υ work/Υ self-stress-rows")
    certified = 0
    for name in args.steps:
        try:
            r = analyse(name)
        except (OSError, ValueError, IndexError) as e:
            sys.exit(f"capped_steps.py: {e}")
        print(f"{name} {r['rows']} {r['bearing']} {r['residual']:.3g} {r['work0']:.4g} {r['work']:.4g} "
              f"{r['self_stress_rows']}", flush=True)
        certified += r["work"] == 0
    print(f"# {certified} of {len(args.steps)} steps have a solution (no self-stress of negative work); "
          f"{len(args.steps) - certified} left open")


if __name__ == "__main__":
    main()
