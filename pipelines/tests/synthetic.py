"""Synthetic inputs for the pipeline's Python tests: gf-shear trajectories laid out as the
gf-shear contract says (H5MD observables every step, /parameters by CLI name plus the
derived packing_fraction, mean_radius, mean_mass, dt, grains), with series the test
chooses, so the analysis can be checked against known answers; gf-incline trajectories;
gf-correlate tables (their layout checked against the real program's output by
test_correlate_schema.py); and ScriptRunner, which runs a pipeline script from a test."""
import os
import subprocess
import sys

import h5py
import numpy as np


def scratch_make(d, *flags):
    """The command line of Makefile.sweeps at SIZE=test with its build, runs and figures in the
    scratch directory d (run it from the repository's root); flags go before the size (-n, -q)."""
    return [
        "make",
        *flags,
        "--no-print-directory",
        "-f",
        "Makefile.sweeps",
        "SIZE=test",
        f"BUILD={d}/build",
        f"RUNS={d}/runs",
        f"FIGURES={d}/figures",
    ]


def ar1(phi, n, rng, burn=2000):
    """Stationary AR(1) series x_t = phi x_{t-1} + eps_t with unit-variance eps."""
    eps = rng.normal(size=n + burn)
    x = np.empty_like(eps)
    x[0] = eps[0] / np.sqrt(1 - phi**2)
    for i in range(1, len(eps)):
        x[i] = phi * x[i - 1] + eps[i]
    return x[burn:]


def ar1_mean_se(phi, n):
    """Exact standard error of the mean of n samples of ar1(phi) (unit-variance noise)."""
    k = np.arange(1, n)
    return np.sqrt((1 + 2 * np.sum((1 - k / n) * phi**k)) / ((1 - phi**2) * n))


def _element(group, name, value, steps, times, unit=None):
    g = group.create_group(name)
    g.create_dataset("step", data=np.asarray(steps, dtype=np.int64))
    g.create_dataset("time", data=np.asarray(times, dtype=float))
    if unit is not None:
        g["time"].attrs["unit"] = unit
    g.create_dataset("value", data=value)


def _tensor(pressure, shear, n1):
    """[rows][2][2] with half trace `pressure`, -xy = `shear`, (xx-yy)/2 = n1 * pressure."""
    t = np.zeros((len(pressure), 2, 2))
    t[:, 0, 0] = pressure * (1 + n1)
    t[:, 1, 1] = pressure * (1 - n1)
    t[:, 0, 1] = t[:, 1, 0] = -shear
    return t


def write_run(
    path,
    pressure_static,
    pressure_kinetic,
    shear_stress,
    temperature,
    *,
    rate=1e-2,
    strain_step=1e-3,
    restitution=0.0,
    friction=0.0,
    packing_fraction=0.8,
    n1=0.01,
    grains=16,
    mean_radius=0.7,
    seed=1,
    frame_every=50,
    rng=None,
):
    """Write a trajectory whose rows are steps 1..n; the stresses are split as
    kinetic + static (total), with the collisional part 0.9 x static."""
    rng = rng or np.random.default_rng(seed)
    ps, pk, s, temp = (
        np.asarray(a, dtype=float) for a in (pressure_static, pressure_kinetic, shear_stress, temperature)
    )
    n = len(ps)
    steps = np.arange(1, n + 1)
    dt = strain_step / rate
    times = steps * dt
    radius = mean_radius * (1 + 0.26 * rng.uniform(-1, 1, grains))
    mass = np.pi * radius**2
    side = np.sqrt(mass.sum() / packing_fraction)
    p = ps + pk
    with h5py.File(path, "w") as f:
        f.attrs["note"] = "synthetic gf-shear trajectory (tests)"
        prm = f.create_group("parameters")
        prm.attrs.update(
            {
                "rate": rate,
                "strain": n * strain_step,
                "strain-step": strain_step,
                "restitution": restitution,
                "tangential-restitution": restitution,
                "friction": friction,
                "frame-every": np.int64(frame_every),
                "seed": np.int64(seed),
                "packing_fraction": packing_fraction,
                "mean_radius": float(radius.mean()),
                "mean_mass": float(mass.mean()),
                "dt": dt,
                "grains": np.int64(grains),
                "program": "gf-shear",
            }
        )
        obs = f.create_group("observables")
        for name, value in (
            ("strain", times * rate),
            ("pressure", p),
            ("shear_stress", s),
            ("normal_stress_difference", np.full(n, n1)),
            ("temperature", temp),
            ("stress_kinetic", _tensor(pk, s * pk / p, n1)),
            ("stress_static", _tensor(ps, s * ps / p, n1)),
            ("stress_collisional", _tensor(0.9 * ps, 0.9 * s * ps / p, n1)),
            ("contacts", np.full(n, grains, dtype=np.int64)),
            ("solver_iterations", np.full(n, 10, dtype=np.int64)),
            ("solver_residual", np.full(n, 1e-12)),
            ("max_overlap", np.full(n, 1e-10)),
        ):
            _element(obs, name, value, steps, times)
        frames = np.concatenate(([0], steps[frame_every - 1 :: frame_every]))
        g = f.create_group("particles/grains")
        g.create_dataset("radius", data=radius)
        g.create_dataset("mass", data=mass)
        pos = rng.uniform(0, side, (len(frames), grains, 2))
        vel = rng.normal(0, 0.1 * rate * side, (len(frames), grains, 2))
        vel[:, :, 0] += rate * (pos[:, :, 1] - side / 2)
        offset = (rate * side * frames * dt) % side
        edges = np.zeros((len(frames), 2, 2))
        edges[:, 0, 0] = edges[:, 1, 1] = side
        edges[:, 1, 0] = offset
        _element(g, "position", pos, frames, frames * dt)
        _element(g, "velocity", vel, frames, frames * dt)
        _element(g, "box/edges", edges, frames, frames * dt)
        g["box"].attrs["dimension"] = 2
        le = f.create_group("lees_edwards")
        le.attrs["rate"] = rate
        _element(le, "offset", offset, frames, frames * dt)
    return path


def write_packing(path, packing_fraction=0.8, grains=16, seed=1):
    """The parts of a gf-pack packing that the report reads."""
    with h5py.File(path, "w") as f:
        f.create_group("parameters").attrs.update(
            {"packing-fraction": packing_fraction, "mean-diameter": 1.4, "seed": np.int64(seed)}
        )
        f.create_dataset("particles/grains/radius", data=np.full(grains, 0.7))
        obs = f.create_group("observables")
        for name, value in (("packing_fraction", packing_fraction), ("max_overlap", 1e-10), ("minimiser_iterations", 100)):
            _element(obs, name, np.array([value]), [0], [0.0])
    return path


def correlation_row(r, xi, amplitude=0.05, contact=1.4, oscillation=None, noise=0.0, rng=None):
    """A C̄(ℓ) row: zero inside `contact`, amplitude·exp(−(ℓ−contact)/ξ) beyond, times
    cos(2πℓ/oscillation) if given (sign changes), plus Gaussian noise of s.d. `noise`."""
    rng = rng or np.random.default_rng(0)
    c = np.where(r >= contact, amplitude * np.exp(-(r - contact) / xi), 0.0)
    if oscillation:
        c = c * np.cos(2 * np.pi * (r - contact) / oscillation)
    return c + noise * rng.normal(size=len(r)), np.full(len(r), noise if noise > 0 else 1e-12)


def write_correlate_table(
    path,
    rows,
    *,
    sigma=1.4,
    bin_width=0.07,
    max_lag=21.0,
    angle_bins=24,
    grains=1000,
    frames=200,
    reference=(),
    xi_abs_el=(1.7, 0.01),
    sweep_abs=(),
    rng=None,
):
    """A gf-correlate output with the datasets the chapter-5 scripts read. `rows` is a list of
    dicts: input, packing_fraction, restitution, friction, C, C_error (over the radial bins of
    bin_width up to max_lag), and optionally xi, xi_error (eq. 5.2), a0, theta0 (ξ(θ) made from
    eq. 5.3), xi_abs, xi_abs_error, measurable, xi_abs_tail (gf-correlate's ξ_|C|; ξ_|C|(θ) made
    from eq. 5.3 with a0_abs), peak, peak_confidence, force_mode (where P(f) peaks; 0 = at f = 0).
    xi_abs_el = (value, error); sweep_abs: per (e, μ) dicts restitution, friction, nu_bc,
    nu_bc_error, status (int), runs (series not given: status 2, all below)."""
    rng = rng or np.random.default_rng(3)
    nb = int(round(max_lag / bin_width))
    r = (np.arange(nb) + 0.5) * bin_width
    theta = (np.arange(angle_bins) + 0.5) * np.pi / angle_bins
    f = (np.arange(200) + 0.5) * 0.05
    n = len(rows)
    col = lambda name, default=np.nan: np.array([row.get(name, default) for row in rows], dtype=float)  # noqa: E731
    xi = col("xi", 1.5)
    xi_theta = np.array(
        [
            x / (2 * np.pi) * (1 - row.get("a0", 0.3) * np.sin(2 * (theta - row.get("theta0", 0.0))))
            for x, row in zip(xi, rows)
        ]
    )
    xi_theta_error = 0.02 * np.abs(xi_theta).mean(axis=1, keepdims=True) * np.ones_like(xi_theta)
    xi_theta = xi_theta + xi_theta_error * rng.normal(size=xi_theta.shape)

    def pdf(mode):
        p = f * np.exp(-f / mode) if mode > 0 else np.exp(-f)
        return p / (p.sum() * 0.05)

    P = np.array([pdf(row.get("force_mode", 1.0)) for row in rows])
    with h5py.File(path, "w") as out:
        out.create_group("parameters").attrs["program"] = "gf-correlate"
        g = out.create_group("runs")
        g["input"] = np.array([row["input"].encode() for row in rows])
        for name in ("packing_fraction", "restitution", "friction"):
            g[name] = col(name)
        g["grains"] = np.full(n, grains, dtype=np.int64)
        g["frames"] = np.full(n, frames, dtype=np.int64)
        g["first_strain"], g["last_strain"] = np.full(n, 0.5), np.full(n, 5.0)
        c = out.create_group("correlation")
        c.attrs.update(
            {
                "mean_diameter": sigma,
                "bin_width": bin_width,
                "max_lag": max_lag,
                "angle_bins": angle_bins,
                "from_strain": 0.5,
                "detect_transient": np.int64(1),
            }
        )
        c["r"] = r
        c["C"] = np.array([row["C"] for row in rows])
        c["C_error"] = np.array([row["C_error"] for row in rows])
        c["xi"], c["xi_error"] = xi, col("xi_error", 0.01)
        c["theta"], c["xi_theta"], c["xi_theta_error"] = theta, xi_theta, xi_theta_error
        for name in ("a0", "theta0"):
            c[name] = col(name, 0.3 if name == "a0" else 0.0)
            c[name + "_error"] = np.full(n, 0.02)
        c["fit_chi2_dof"] = np.ones(n)
        c.attrs.update(
            {
                "abs_bin_width": 5 * bin_width,
                "abs_noise": 2.0,
                "abs_threshold": "soft",
                "abs_tail_from": 2 / 3,
                "abs_max_tail_share": 0.05,
            }
        )
        xi_abs = col("xi_abs", 1.5)
        c["xi_abs"], c["xi_abs_error"] = xi_abs, col("xi_abs_error", 0.02)
        c["measurable"] = col("measurable", 1).astype(np.int32)
        c["xi_abs_tail"] = col("xi_abs_tail", 0.0)
        c["xi_abs_tail_error"] = np.full(n, 0.001)
        c["xi_abs_el"], c["xi_abs_el_error"] = float(xi_abs_el[0]), float(xi_abs_el[1])
        ratio = xi_abs / xi_abs_el[0]
        c["xi_abs_ratio"] = ratio
        c["xi_abs_ratio_error"] = np.abs(ratio) * np.hypot(
            col("xi_abs_error", 0.02) / xi_abs, xi_abs_el[1] / xi_abs_el[0]
        )
        a0_abs = col("a0_abs", 0.1)
        c["xi_abs_theta"] = np.array([x * (1 - a * np.sin(2 * theta)) for x, a in zip(xi_abs, a0_abs)])
        c["xi_abs_theta_error"] = 0.01 * np.abs(c["xi_abs_theta"][()])
        c["a0_abs"], c["a0_abs_error"] = a0_abs, np.full(n, 0.01)
        c["theta0_abs"], c["theta0_abs_error"] = np.zeros(n), np.full(n, 0.01)
        fo = out.create_group("forces")
        fo["f"], fo["f_bc"] = f, f
        fo["P"], fo["P_bc"] = P, np.array([pdf(1.0)] * n)
        fo["P_error"], fo["P_bc_error"] = 0.02 * P, 0.02 * P
        fo["peak"] = col("peak", 1).astype(np.int64)
        fo["peak_confidence"] = col("peak_confidence", 1.0)
        if reference:
            out.create_group("reference")["input"] = np.array([p.encode() for p in reference])
        keys = sorted({(row["restitution"], row["friction"]) for row in rows})
        s = out.create_group("sweep")
        s["restitution"] = np.array([k[0] for k in keys])
        s["friction"] = np.array([k[1] for k in keys])
        s.attrs["threshold"] = 1.25
        s["nu_bc"], s["nu_bc_error"] = np.full(len(keys), np.nan), np.full(len(keys), np.nan)
        s["status"] = np.full(len(keys), 2, dtype=np.int64)
        given = {(g["restitution"], g["friction"]): g for g in sweep_abs}
        rows_of = lambda k: sum(
            1 for row in rows if (row["restitution"], row["friction"]) == k and row.get("measurable", 1)  # noqa: E731
        )
        pick = lambda name, k, default: given[k].get(name, default) if k in given else default  # noqa: E731
        s["nu_bc_abs"] = np.array([pick("nu_bc", k, np.nan) for k in keys])
        s["nu_bc_abs_error"] = np.array([pick("nu_bc_error", k, np.nan) for k in keys])
        s["nu_below_abs"] = np.array([pick("nu_below", k, np.nan) for k in keys])
        s["nu_above_abs"] = np.array([pick("nu_above", k, np.nan) for k in keys])
        s["status_abs"] = np.array([pick("status", k, 2) for k in keys], dtype=np.int32)
        s["runs_abs"] = np.array([pick("runs", k, rows_of(k)) for k in keys], dtype=np.int32)
    return path


def write_clusters_table(path, run_paths, labels_per_run, side=10.0, rng=None):
    """A gf-correlate output with /clusters for the given runs (positions uniform in the box)."""
    rng = rng or np.random.default_rng(4)
    labels = np.concatenate(labels_per_run).astype(np.int32)
    offsets = np.concatenate(([0], np.cumsum([len(x) for x in labels_per_run])))
    with h5py.File(path, "w") as out:
        out.create_group("parameters")
        g = out.create_group("runs")
        g["input"] = np.array([p.encode() for p in run_paths])
        g["packing_fraction"] = np.full(len(run_paths), 0.79)
        g["restitution"] = np.linspace(0.92, 0.0, len(run_paths))
        g["friction"] = np.zeros(len(run_paths))
        g["grains"] = np.array([len(x) for x in labels_per_run], dtype=np.int64)
        c = out.create_group("clusters")
        c["label"] = labels
        c["position"] = rng.uniform(0, side, (len(labels), 2))
        c["grain_offset"] = offsets.astype(np.int64)
        c["box"] = np.array([[side, side, 0.3 * side]] * len(run_paths))
        c["count"] = np.array([x.max() for x in labels_per_run], dtype=np.int64)
        c["first_step"] = np.zeros(len(run_paths), dtype=np.int64)
        c["last_step"] = np.ones(len(run_paths), dtype=np.int64)
    return path


# The chapter-5 sweep of chapter5_tables(): ξ_|C| = 1.7 + 3(ν − 0.55 − 0.2e)+ (+0.5 with
# friction at ν > 0.7) crosses 1.25 ξ_el = 1.25·1.7 at ν = 0.6917 + 0.2e: the ν_bc gf-correlate
# would write, given to the table; two dense runs flagged as not measurable.
CH5_NU_BC = {(0.0, 0.0): 0.6917, (0.25, 0.0): 0.7417, (0.5, 0.0): 0.7917, (0.0, 0.4): 0.66}
CH5_NOT_MEASURABLE = {(0.81, 0.0, 0.0), (0.81, 0.0, 0.4)}


def chapter5_tables(d):
    """A synthetic chapter-5 sweep in directory d, with known ξ_|C|, flags and ν_bc: the
    gf-correlate table (ch5_correlate.h5, every e at μ = 0 and μ = 0.4 at e = 0, five ν each,
    the reference at e = 0.92, ν = 0.3), the cluster table of two windows (ch5_clusters.h5) and
    a packing. Returns {"rows", "table", "clusters", "packing"}."""
    rng = np.random.default_rng(11)
    r = (np.arange(300) + 0.5) * 0.07
    rows = []
    for mu in (0.0, 0.4):
        for e in (0.0, 0.25, 0.5, 0.75, 0.92) if mu == 0 else (0.0,):
            for nu in (0.3, 0.6, 0.7, 0.77, 0.81):
                xi = 0.3 + 3.0 * max(0.0, nu - 0.55 - 0.2 * e) + (0.5 if mu > 0 and nu > 0.7 else 0)
                c, err = correlation_row(r, xi, noise=1e-4, rng=rng)
                dense = 1.4 + xi >= 1.25 * 1.7
                rows.append(
                    dict(
                        input=os.path.join(d, f"shear_nu{nu:.3f}_e{e:.2f}_mu{mu:.2f}.h5"),
                        packing_fraction=nu,
                        restitution=e,
                        friction=mu,
                        C=c,
                        C_error=err,
                        xi=1.4 + xi,
                        xi_error=0.05,
                        xi_abs=1.4 + xi,
                        xi_abs_error=0.02,
                        measurable=0 if (nu, e, mu) in CH5_NOT_MEASURABLE else 1,
                        xi_abs_tail=0.2 if (nu, e, mu) in CH5_NOT_MEASURABLE else 0.001,
                        peak=0 if dense else 1,
                        force_mode=0.0 if dense else 0.8,
                    )
                )
    ref = rows[4 * 5 + 0]["input"]  # e = 0.92, ν = 0.3
    sweep = [
        dict(
            restitution=e,
            friction=mu,
            nu_bc=v,
            nu_bc_error=0.004,
            nu_below=0.6 + 0.1 * (v > 0.7),
            nu_above=0.7 + 0.07 * (v > 0.7),
            status=0,
        )
        for (e, mu), v in CH5_NU_BC.items()
    ]
    table = write_correlate_table(
        os.path.join(d, "ch5_correlate.h5"), rows, reference=[ref], xi_abs_el=(1.7, 0.012), sweep_abs=sweep
    )
    runs = [write_packing(os.path.join(d, f"window{k}.h5")) for k in range(2)]
    labels = [np.array([0, 1, 1, 2, 2, 3, 3, 0, 0, 4, 4, 0, 5, 5, 0, 0]), np.array([1] * 10 + [2, 2, 2, 0, 0, 0])]
    clusters = write_clusters_table(os.path.join(d, "ch5_clusters.h5"), runs, labels)
    packing = write_packing(os.path.join(d, "pack.h5"))
    return {"rows": rows, "table": table, "clusters": clusters, "packing": packing}


def bagnold_profiles(
    angle,
    *,
    exponent=1.5,
    height_diameters=25.0,
    mean_radius=0.7,
    nu=0.8,
    bin_diameters=3.0,
    gravity=1.0,
    mt_over_pr2=0.05,
    base_anomaly=0.1,
):
    """Depth profiles of an ideal incline flow, in the gf-incline /profiles layout: ν constant,
    V_x = V_s − c (H − y)^exponent, Σ_yy = g cos θ W and s = g sin θ W with W = ν (H − y)
    (areal density 1), Σ_xx = Σ_yy, T = mt_over_pr2 · p ⟨R⟩²/m; the lowest layer's s/p and T
    are off by base_anomaly (relative), the top layer is half full."""
    d = 2 * mean_radius
    mass = np.pi * mean_radius**2
    bin_ = bin_diameters * d
    height = height_diameters * d
    bins = int(np.ceil(height / bin_))
    y = (np.arange(bins) + 0.5) * bin_
    depth = np.clip(height - y, 0.05 * bin_, None)
    theta = np.radians(angle)
    w = gravity * nu * depth
    nu_profile = np.full(bins, nu)
    nu_profile[-1] = 0.5 * nu
    c = 0.3
    v = c * (height**exponent - depth**exponent)
    rate = c * exponent * depth ** (exponent - 1)
    syy = np.cos(theta) * w
    s = np.sin(theta) * w
    s[0] *= 1 + base_anomaly
    p = syy.copy()
    t = mt_over_pr2 * p * mean_radius**2 / mass
    t[0] *= 1 + base_anomaly
    return {
        "y": y,
        "packing_fraction": nu_profile,
        "velocity_x": v,
        "shear_rate": rate,
        "temperature": t,
        "pressure": p,
        "shear_stress": s,
        "stress_xx": syy.copy(),
        "stress_xy": -s,
        "stress_yy": syy,
        "weight_above": w,
        "s_over_p": s / p,
        "inertial": rate * mean_radius / np.sqrt(t),
        "mT_over_pR2": mass * t / (p * mean_radius**2),
        "_bin": bin_,
        "_height": height,
    }


def write_incline_run(
    path,
    angle,
    *,
    profiles=None,
    flow_rate=None,
    friction=0.0,
    restitution=0.5,
    mean_radius=0.7,
    width_diameters=40.0,
    nu=0.8,
    height_diameters=25.0,
    gravity=1.0,
    time_step=5e-3,
    observe_every=10,
    steady=1,
    steady_from_tau=100.0,
    seed=1,
    parent=None,
    time_unit="tau",
):
    """A gf-incline trajectory with the parts the incline analyses read: /parameters,
    /observables/flow_rate (given series, one row per observe_every steps), /profiles (given,
    or bagnold_profiles) with its attributes, and two frames of grains (a base row and a layer).
    parent = (path, friction, time in τ): a branch, with gf-incline's input and parent_* provenance.
    time_unit: "tau" (gf-incline's files: times in τ, each time dataset and /profiles saying so)
    or "code" (files of code time without unit attributes, steady_from_tau on /profiles)."""
    rng = np.random.default_rng(seed)
    d = 2 * mean_radius
    mass = np.pi * mean_radius**2
    tau = np.sqrt(mean_radius / gravity)
    dt = time_step * tau
    # Code time -> stored time, and the unit attribute of the time datasets.
    stored, unit = (lambda t: t / tau, "tau") if time_unit == "tau" else (lambda t: t, None)
    lx = width_diameters * d
    if profiles is None:
        profiles = bagnold_profiles(
            angle, mean_radius=mean_radius, nu=nu, height_diameters=height_diameters, gravity=gravity
        )
    grains = int(round(nu * lx * height_diameters * d / mass))
    if flow_rate is None:
        flow_rate = np.full(4000, 1.0) + 0.01 * rng.normal(size=4000)
    flow_rate = np.asarray(flow_rate, dtype=float) * np.sqrt(gravity * mean_radius)
    n = len(flow_rate)
    steps = np.arange(1, n + 1) * observe_every
    total_steps = int(steps[-1])
    with h5py.File(path, "w") as f:
        f.attrs["note"] = "synthetic gf-incline trajectory (tests)"
        f.create_group("parameters").attrs.update(
            {
                "angle": float(angle),
                "friction": friction,
                "restitution": restitution,
                "tau": tau,
                "gravity": gravity,
                "dt": dt,
                "total_steps": np.int64(total_steps),
                "grains": np.int64(grains),
                "base_grains": np.int64(int(width_diameters)),
                "mean_radius": mean_radius,
                "mean_mass": mass,
                "observe-every": np.int64(observe_every),
                "program": "gf-incline",
            }
        )
        if parent is not None:
            f["parameters"].attrs.update(
                {
                    "input": parent[0],
                    "input_time": stored(parent[2] * tau),
                    "parent_friction": float(parent[1]),
                    "parent_program": "gf-incline",
                }
            )
        else:
            f["parameters"].attrs["input"] = "incline_pack.h5"
        obs = f.create_group("observables")
        if unit is not None and parent is not None:
            f["parameters"].attrs["input_time_unit"] = unit
        _element(obs, "flow_rate", flow_rate, steps, stored(steps * dt), unit)
        g = f.create_group("profiles")
        for k, v in profiles.items():
            if not k.startswith("_"):
                g.create_dataset(k, data=np.asarray(v, dtype=float))
        g.attrs.update(
            {
                "steady": np.int64(steady),
                "steady_from_given": np.int64(1),
                **(
                    {"steady_from_time": steady_from_tau, "time_unit": "tau"}
                    if time_unit == "tau"
                    else {"steady_from_tau": steady_from_tau}
                ),
                "bin": float(profiles.get("_bin", 3 * d)),
                "layer_length": lx,
                "mean_radius": mean_radius,
                "mean_mass": mass,
                "gravity": gravity,
                "tau": tau,
            }
        )
        base = int(width_diameters)
        radius = np.full(base + 50, mean_radius)
        fixed = np.zeros(len(radius), dtype=np.uint8)
        fixed[:base] = 1
        pos = np.zeros((2, len(radius), 2))
        pos[:, :base, 0] = (np.arange(base) + 0.5) * lx / base
        pos[:, base:, 0] = rng.uniform(0, lx, 50)
        pos[:, base:, 1] = rng.uniform(d, height_diameters * d, 50)
        vel = np.zeros_like(pos)
        vel[:, base:, 0] = 0.1 * pos[:, base:, 1]
        edges = np.tile(np.array([[lx, 0.0], [0.0, (height_diameters + 5) * d]]), (2, 1, 1))
        frames = np.array([0, total_steps])
        pg = f.create_group("particles/grains")
        pg.create_dataset("radius", data=radius)
        pg.create_dataset("mass", data=np.pi * radius**2)
        pg.create_dataset("fixed", data=fixed)
        _element(pg, "position", pos, frames, stored(frames * dt), unit)
        _element(pg, "velocity", vel, frames, stored(frames * dt), unit)
        _element(pg, "box/edges", edges, frames, stored(frames * dt), unit)
    return path


class ScriptRunner:
    """Mixin for unittest.TestCase: runs a pipeline script (path relative to pipelines/) with
    this Python and fails the test, with its stderr, if the script fails."""

    def run_script(self, script, *args):
        pipelines = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
        res = subprocess.run([sys.executable, os.path.join(pipelines, script), *args], capture_output=True, text=True)
        self.assertEqual(res.returncode, 0, res.stderr)
        return res


KINETIC_COLUMNS = (
    "packing_fraction restitution friction tangential_restitution rate first_strain last_strain temperature "
    "temperature_error chi chi_error p0 eta0 p_static p_static_error p_collisional p_collisional_error s_static "
    "s_static_error s_collisional s_collisional_error p_enskog p_enskog_error s_enskog_thesis s_enskog_2d "
    "collision_frequency collision_frequency_error collision_frequency_frames collision_frequency_frames_error "
    "velocity_correlation velocity_correlation_error velocity_correlation_frames velocity_correlation_frames_error "
    "energy_balance energy_balance_error"
).split()


def write_kinetic_table(path, rows, equilibrium=(), grains=1000):
    """A gf-kinetic output laid out as docs/file-format.md (contract B) says: `rows` are dicts of
    the /runs columns (input and any of KINETIC_COLUMNS; missing ones NaN, chi_source 0),
    `equilibrium` dicts of the /equilibrium columns."""
    n = len(rows)
    with h5py.File(path, "w") as out:
        out.create_group("parameters").attrs["program"] = "gf-kinetic"
        g = out.create_group("runs")
        g.attrs.update(
            {
                "velocity_correlation_convention": "per collision",
                "velocity_correlation_baseline": -0.25,
                "temperature_definition": "<|V|^2> about the mean flow, translational, not mass-weighted",
                "from_strain": 0.5,
                "detect_transient": np.int64(1),
            }
        )
        g["input"] = np.array([row["input"].encode() for row in rows])
        g["grains"] = np.full(n, grains, dtype=np.int32)
        g["chi_source"] = np.array([row.get("chi_source", 0) for row in rows], dtype=np.int32)
        for name in KINETIC_COLUMNS:
            g[name] = np.array([row.get(name, np.nan) for row in rows], dtype=float)
            g[name].attrs["rows"] = "runs"
        if equilibrium:
            q = out.create_group("equilibrium")
            q["input"] = np.array([row["input"].encode() for row in equilibrium])
            q["grains"] = np.full(len(equilibrium), grains, dtype=np.int32)
            for name in (
                "packing_fraction temperature temperature_drift energy_drift collision_frequency collision_frequency_error chi "
                "chi_error compressibility compressibility_error chi_virial chi_virial_error chi_virial_thesis_temperature "
                "chi_virial_thesis_temperature_error chi_henderson"
            ).split():
                q[name] = np.array([row.get(name, np.nan) for row in equilibrium], dtype=float)
    return path


# The chapter-6 sweep of chapter6_tables(), by e: the last ν of the binary-collision range
# (p^bc = p^s exactly up to it, half of p^s beyond; None: they differ at the most dilute ν too),
# the ν where they agree again, the last ν where p^s is within 5 % of the Enskog pressure, and the
# excess of C_v over its baseline (NaN: not measured). ξ/ξ_el > 1.25 from ν = 0.7 on (filled).
CH6_NU = (0.3, 0.5, 0.6, 0.7, 0.8)
CH6_AGREE_UPTO = {0.92: 0.6, 0.75: 0.6, 0.5: 0.5, 0.25: None, 0.1: 0.5, 0.0: 0.3}
CH6_AGREE_AGAIN = {0.75: [0.8]}
CH6_PRESSURE_UPTO = {0.92: 0.5, 0.75: 0.5, 0.5: 0.6, 0.25: 0.3, 0.1: 0.3, 0.0: None}
CH6_CV_EXCESS = {0.92: 0.02, 0.75: 0.05, 0.5: 0.1, 0.25: 0.15, 0.1: np.nan, 0.0: 0.2}
CH6_FILLED_FROM = 0.7


def chapter6_tables(d):
    """A synthetic chapter-6 sweep in directory d with the known answers above: gf-kinetic's table
    (ch6_kinetic.h5, six e × five ν, two equilibrium rows), gf-correlate's (ch5_correlate.h5, the
    same runs, ξ/ξ_el = 1.1 below CH6_FILLED_FROM and 1.5 from it) and a packing. At e = 0.92,
    ν = 0.3, s^s is 1.05 times the 2D Garzó–Dufty prediction, which eq. 6.10 as printed exceeds
    2.2 times; elsewhere the relative error of eq. 6.10 is 4·(C_v − baseline). Returns
    {"kinetic", "correlate", "packing", "rows"}."""
    p0, eta0, rate = 2.0, 0.5, 0.01
    rows, correlate_rows = [], []
    r = (np.arange(300) + 0.5) * 0.07
    for e, upto in CH6_AGREE_UPTO.items():
        for nu in CH6_NU:
            chi = 1 / (1 - nu / 0.9)
            p_enskog = p0 * (1 + e) * chi * nu
            pupto = CH6_PRESSURE_UPTO[e]
            p_static = p_enskog * (1.02 if pupto is not None and nu <= pupto + 1e-9 else 1.08)
            same = (upto is not None and nu <= upto + 1e-9) or nu in CH6_AGREE_AGAIN.get(e, [])
            p_coll = p_static if same else 0.5 * p_static
            excess = CH6_CV_EXCESS[e]
            s_2d = rate * eta0 * 3.0 * nu
            s_thesis = 2.2 * s_2d
            s_static = s_2d * 1.05 if (e == 0.92 and nu == 0.3) else s_thesis / (1 + 4 * (excess if excess == excess else 0.1))
            path = os.path.join(d, f"shear_nu{nu:.3f}_e{e:.2f}_mu0.00_r1e-02_s1.h5")
            rows.append(
                dict(
                    input=path,
                    packing_fraction=nu,
                    restitution=e,
                    friction=0.0,
                    rate=rate,
                    p0=p0,
                    eta0=eta0,
                    chi=chi,
                    chi_error=0.01,
                    p_enskog=p_enskog,
                    p_enskog_error=0.01 * p_enskog,
                    p_static=p_static,
                    p_static_error=0.01 * p_static,
                    p_collisional=p_coll,
                    p_collisional_error=0.01 * p_coll,
                    s_static=s_static,
                    s_static_error=0.01 * s_static,
                    s_collisional=0.9 * s_static,
                    s_collisional_error=0.01 * s_static,
                    s_enskog_thesis=s_thesis,
                    s_enskog_2d=s_2d,
                    velocity_correlation=-0.25 + excess,
                    velocity_correlation_error=0.005,
                )
            )
            ratio = 1.5 if nu >= CH6_FILLED_FROM - 1e-9 else 1.1
            correlate_rows.append(
                dict(
                    input=path,
                    packing_fraction=nu,
                    restitution=e,
                    friction=0.0,
                    C=np.zeros(len(r)),
                    C_error=np.full(len(r), 1e-3),
                    xi_abs=ratio * 1.7,
                )
            )
    equilibrium = [
        dict(input=os.path.join(d, f"eq_nu{nu:.3f}_s1.h5"), packing_fraction=nu, chi=1 / (1 - nu / 0.9),
             chi_error=0.01, chi_virial=1 / (1 - nu / 0.9), chi_virial_error=0.02, temperature_drift=0.001,
             chi_henderson=1 / (1 - nu / 0.9))
        for nu in (0.3, 0.8)
    ]
    kinetic = write_kinetic_table(os.path.join(d, "ch6_kinetic.h5"), rows, equilibrium)
    correlate = write_correlate_table(
        os.path.join(d, "ch5_correlate.h5"), correlate_rows, reference=[correlate_rows[0]["input"]],
        xi_abs_el=(1.7, 0.012),
    )
    packing = write_packing(os.path.join(d, "pack.h5"))
    return {"kinetic": kinetic, "correlate": correlate, "packing": packing, "rows": rows}


# gf-network's table (issue-22 contract; docs/file-format.md): the per-run columns of /runs
# (each value with its _error where the contract has one) and of /prediction.
NETWORK_RUN_COLUMNS = (
    "packing_fraction restitution friction tangential_restitution rate dt first_strain last_strain contacts "
    "long_lived fabric_norm a_f_first_order a_f_prime_first_order mean_binary_force sigma_anisotropy "
    "sigma_max_deviation"
).split()
NETWORK_RUN_WITH_ERRORS = (
    "coordination coordination_active mean_cos_deflection mean_cos_cos2_deflection Phi Psi phi_11 phi_22 phi_12 "
    "chi_11 chi_22 chi_12 a_c a_c_prime a_f a_f_prime a4_c a4_c_prime a4_f a4_f_prime p_static p_collisional "
    "s_static s_collisional sxx_static sxx_collisional shear_ratio_collisional shear_ratio_collisional_frames"
).split()
NETWORK_PREDICTION_WITH_ERRORS = [f"lhs_{q}" for q in ("pressure", "shear", "xx")] + [
    f"rhs_{q}{r}" for r in ("", "_floor", "_active", "_unit") for q in ("pressure", "shear", "xx")
]
NETWORK_PREDICTION_COLUMNS = "xi_ratio xi_ratio_error sum_limit network_factor path_factor".split()


def write_network_table(path, rows, angle_bins=36, deflection_bins=36, xi_source="correlation"):
    """A gf-network output laid out as the contract says: `rows` are dicts of the /runs and
    /prediction columns (input and any of the names above; missing ones NaN, errors NaN unless
    given; grains, frames, xi_measurable, continuation_real ints). /histograms: C(θ) and F_bc(θ)
    of the first-order forms with each row's a_c, a′_c, a_f, a′_f (0 where NaN), σ(θ) = 1 and a
    uniform P_C over |x| ≤ 2π/3."""
    n = len(rows)
    theta = (np.arange(angle_bins) + 0.5) * np.pi / angle_bins
    x = (np.arange(deflection_bins) + 0.5) * np.pi / deflection_bins

    def value(row, name):
        v = row.get(name, np.nan)
        return v if v == v else 0.0

    with h5py.File(path, "w") as out:
        prm = out.create_group("parameters")
        prm.attrs["program"] = "gf-network"
        prm.attrs["angle_bins"] = np.int64(angle_bins)
        prm.attrs["deflection_bins"] = np.int64(deflection_bins)
        g = out.create_group("runs")
        g["input"] = np.array([row["input"].encode() for row in rows])
        for name in ("grains", "frames"):
            g[name] = np.array([row.get(name, 1000 if name == "grains" else 100) for row in rows], dtype=np.int32)
        names = NETWORK_RUN_COLUMNS + [m for n_ in NETWORK_RUN_WITH_ERRORS for m in (n_, n_ + "_error")]
        for name in names:
            g[name] = np.array([row.get(name, np.nan) for row in rows], dtype=float)
            g[name].attrs.update({"rows": "runs", "meaning": name, "units": "1"})
        p = out.create_group("prediction")
        if xi_source == "none":
            p.attrs["xi_source"] = "none"
        names = NETWORK_PREDICTION_COLUMNS + [m for n_ in NETWORK_PREDICTION_WITH_ERRORS for m in (n_, n_ + "_error")]
        for name in names:
            p[name] = np.array([row.get(name, np.nan) for row in rows], dtype=float)
            p[name].attrs.update({"rows": "runs", "meaning": name, "units": "1"})
        for name in ("xi_measurable", "continuation_real"):
            p[name] = np.array([row.get(name, 1) for row in rows], dtype=np.int32)
        h = out.create_group("histograms")
        h["theta"] = theta
        h["deflection"] = x
        s2, c2 = np.sin(2 * theta), np.cos(2 * theta)
        h["C"] = np.array([(1 + value(r, "a_c") * s2 + value(r, "a_c_prime") * c2) / (2 * np.pi) for r in rows])
        h["binary_force"] = np.array([1 + value(r, "a_f") * s2 + value(r, "a_f_prime") * c2 for r in rows])
        h["sigma"] = np.ones((n, angle_bins))
        h["P_C"] = np.tile(np.where(x <= 2 * np.pi / 3, 3 / (4 * np.pi), 0.0), (n, 1))
    return path
