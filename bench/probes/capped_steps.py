#!/usr/bin/env python3
"""Does a frictional step left at the sweep cap have a solution at all?

Reads the files that dump_capped_steps.patch writes (one per step: the bodies' velocities and
inverse masses, every row's grains, normal, bounds b_n and b_t, 1/W_nn and impulses) and
answers two linear programs per step (HiGHS, through SciPy):

  feasible  the least t such that some impulses within the Coulomb cones (P_n >= 0,
            |P_t| <= mu P_n) give u_n >= b_n - t on every row; 0 when the normal
            constraints can all be met. Necessary for a solution.
  work      the work -(P_n b_n + P_t b_t), per unit of its sum P_n, of the self-stress
            within the cones (impulses, 0 <= P_n <= 1, with no net impulse or torque on any
            grain) that does the least work; 0 when none does negative work. Then the step's linear complementarity
            problem (the region solves' form, docs/method/solver.md) has a solution: its
            matrix is copositive (Anitescu & Potra 1997) and every solution of the
            homogeneous problem is such a self-stress, so Cottle, Pang & Stone's
            theorem 3.8.6 applies. A negative value leaves existence open: a solution must
            then slide at contacts of that self-stress.
  work0     the same without friction (P_t = 0): 0 means the frictionless problem of the
            same rows has a solution (its matrix is positive semi-definite).

Needs python3-numpy and python3-scipy. Usage: capped_steps.py DIR/step*.txt
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
    with open(name) as f:
        head = f.readline().split()
        if head[:2] != ["#", "mu"]:
            raise ValueError(f"{name}: not a dump of dump_capped_steps.patch")
        mu, upsilon, residual = float(head[2]), float(head[4]), float(head[6])
        bodies, rows = [], []
        for line in f:
            kind, *values = line.split()
            (bodies if kind == "B" else rows).append([float(v) for v in values])
    return mu, upsilon, residual, np.array(bodies), np.array(rows)


def impulse_map(rows, n_bodies):
    """H: the net impulse (x, y) and R-scaled torque on each grain of unit P_n and P_t per row
    (columns 2c and 2c + 1), so that the velocity change is diag(1/m) H P."""
    i, j = rows[:, 0].astype(int), rows[:, 1].astype(int)
    nx, ny = rows[:, 2], rows[:, 3]
    r, c, v = [], [], []
    for body, s in ((i, 1.0), (j, -1.0)):
        for dof, pn_part, pt_part in ((0, nx, -ny), (1, ny, nx), (2, 0 * nx, -2.0 + 0 * nx)):
            sign = s if dof < 2 else 1.0  # the torque of ±P at the contact point has one sign
            r += [3 * body + dof, 3 * body + dof]
            c += [2 * np.arange(len(rows)), 2 * np.arange(len(rows)) + 1]
            v += [sign * pn_part, sign * pt_part]
    return sp.csr_matrix((np.concatenate(v), (np.concatenate(r), np.concatenate(c))), shape=(3 * n_bodies, 2 * len(rows)))


def cone(mu, n_rows, extra=0):
    """|P_t| <= mu P_n as two rows per contact (P_t - mu P_n <= 0, -P_t - mu P_n <= 0)."""
    k = np.arange(n_rows)
    r = np.concatenate([2 * k, 2 * k, 2 * k + 1, 2 * k + 1])
    c = np.concatenate([2 * k + 1, 2 * k, 2 * k + 1, 2 * k])
    v = np.concatenate([np.ones(n_rows), -mu * np.ones(n_rows), -np.ones(n_rows), -mu * np.ones(n_rows)])
    return sp.csr_matrix((v, (r, c)), shape=(2 * n_rows, 2 * n_rows + extra))


def analyse(name):
    mu, upsilon, residual, bodies, rows = load(name)
    n_rows = len(rows)
    inv_mass = np.repeat(bodies[:, 3], 3)
    H = impulse_map(rows, len(bodies))
    P_now = np.empty(2 * n_rows)
    P_now[0::2], P_now[1::2] = rows[:, 7], rows[:, 8]
    v_free = bodies[:, :3].reshape(-1) - inv_mass * (H @ P_now)
    # u_n of each row: (v_i - v_j)·n.
    i, j = rows[:, 0].astype(int), rows[:, 1].astype(int)
    k = np.arange(n_rows)
    N = sp.csr_matrix((np.concatenate([rows[:, 2], rows[:, 3], -rows[:, 2], -rows[:, 3]]),
                       (np.tile(k, 4), np.concatenate([3 * i, 3 * i + 1, 3 * j, 3 * j + 1]))),
                      shape=(n_rows, 3 * len(bodies)))
    A = (N @ sp.diags(inv_mass) @ H).tocsr()  # u_n = N v_free + A P
    need = rows[:, 4] - N @ v_free             # A P >= need
    v_scale = max(np.abs(need).max(), upsilon)
    p_scale = v_scale / bodies[:, 3].mean()

    # Least uniform violation t of the normal constraints (variables P / p_scale, t / v_scale).
    n = 2 * n_rows
    A_ub = sp.vstack([sp.hstack([-A * (p_scale / v_scale), -sp.csr_matrix(np.ones((n_rows, 1)))]),
                      cone(mu, n_rows, extra=1)]).tocsr()
    b_ub = np.concatenate([-need / v_scale, np.zeros(n)])
    cost = np.zeros(n + 1)
    cost[-1] = 1
    bounds = [(0, None), (None, None)] * n_rows + [(0, None)]
    lp = linprog(cost, A_ub=A_ub, b_ub=b_ub, bounds=bounds, method="highs")
    feasible = lp.x[-1] * v_scale / upsilon if lp.status == 0 else float("nan")

    def least_work(friction):
        # Self-stresses: H P = 0, P in the cones, 0 <= P_n <= 1; minimise -(P·b).
        used = np.flatnonzero(np.diff(H.indptr))
        cost = np.empty(n)
        cost[0::2], cost[1::2] = -rows[:, 4] / v_scale, -rows[:, 5] / v_scale
        pt_bound = (None, None) if friction else (0, 0)
        lp = linprog(cost, A_ub=cone(mu, n_rows), b_ub=np.zeros(n), A_eq=H[used], b_eq=np.zeros(len(used)),
                     bounds=[(0, 1), pt_bound] * n_rows, method="highs")
        if lp.status != 0:
            return float("nan"), 0
        total = lp.x[0::2].sum()
        return (lp.fun / total * v_scale / upsilon if total > 0 else 0.0), int((lp.x[0::2] > 1e-9).sum())

    work, used = least_work(True)
    work0, _ = least_work(False)
    return dict(rows=n_rows, bearing=int((rows[:, 7] > 0).sum()), residual=residual / upsilon,
                feasible=feasible, work=work, self_stress_rows=used, work0=work0)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("steps", nargs="+", help="step files written by dump_capped_steps.patch")
    args = parser.parse_args()
    print("step rows bearing residual/Υ feasible/Υ work/Υ self-stress-rows work0/Υ")
    certified = open_ = 0
    for name in args.steps:
        try:
            r = analyse(name)
        except (OSError, ValueError, IndexError) as e:
            sys.exit(f"capped_steps.py: {e}")
        print(f"{name} {r['rows']} {r['bearing']} {r['residual']:.3g} {r['feasible']:.3g} {r['work']:.4g} "
              f"{r['self_stress_rows']} {r['work0']:.4g}", flush=True)
        if r["feasible"] == 0 and r["work"] == 0:
            certified += 1
        else:
            open_ += 1
    print(f"# {certified} of {certified + open_} steps have a solution (no self-stress of negative work); "
          f"{open_} left open")


if __name__ == "__main__":
    main()
