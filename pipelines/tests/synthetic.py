"""Synthetic gf-shear trajectories for the pipeline's Python tests: files laid out as the
gf-shear contract says (H5MD observables every step, /parameters by CLI name plus the
derived packing_fraction, mean_radius, mean_mass, dt, grains), with series the test
chooses, so the analysis can be checked against known answers."""
import h5py
import numpy as np


def ar1(phi, n, rng, burn=2000):
    """Stationary AR(1) series x_t = phi x_{t-1} + eps_t with unit-variance eps."""
    eps = rng.normal(size=n + burn)
    x = np.empty_like(eps)
    x[0] = eps[0] / np.sqrt(1 - phi ** 2)
    for i in range(1, len(eps)):
        x[i] = phi * x[i - 1] + eps[i]
    return x[burn:]


def ar1_mean_se(phi, n):
    """Exact standard error of the mean of n samples of ar1(phi) (unit-variance noise)."""
    k = np.arange(1, n)
    return np.sqrt((1 + 2 * np.sum((1 - k / n) * phi ** k)) / ((1 - phi ** 2) * n))


def _element(group, name, value, steps, times):
    g = group.create_group(name)
    g.create_dataset("step", data=np.asarray(steps, dtype=np.int64))
    g.create_dataset("time", data=np.asarray(times, dtype=float))
    g.create_dataset("value", data=value)


def _tensor(pressure, shear, n1):
    """[rows][2][2] with half trace `pressure`, -xy = `shear`, (xx-yy)/2 = n1 * pressure."""
    t = np.zeros((len(pressure), 2, 2))
    t[:, 0, 0] = pressure * (1 + n1)
    t[:, 1, 1] = pressure * (1 - n1)
    t[:, 0, 1] = t[:, 1, 0] = -shear
    return t


def write_run(path, pressure_static, pressure_kinetic, shear_stress, temperature, *, rate=1e-2,
              strain_step=1e-3, restitution=0.0, friction=0.0, packing_fraction=0.8, n1=0.01,
              grains=16, mean_radius=0.7, seed=1, frame_every=50, rng=None):
    """Write a trajectory whose rows are steps 1..n; the stresses are split as
    kinetic + static (total), with the collisional part 0.9 x static."""
    rng = rng or np.random.default_rng(seed)
    ps, pk, s, temp = (np.asarray(a, dtype=float) for a in (pressure_static, pressure_kinetic,
                                                              shear_stress, temperature))
    n = len(ps)
    steps = np.arange(1, n + 1)
    dt = strain_step / rate
    times = steps * dt
    radius = mean_radius * (1 + 0.26 * rng.uniform(-1, 1, grains))
    mass = np.pi * radius ** 2
    side = np.sqrt(mass.sum() / packing_fraction)
    p = ps + pk
    with h5py.File(path, "w") as f:
        f.attrs["note"] = "synthetic gf-shear trajectory (tests)"
        prm = f.create_group("parameters")
        prm.attrs.update({"rate": rate, "strain": n * strain_step, "strain-step": strain_step,
                          "restitution": restitution, "tangential-restitution": restitution,
                          "friction": friction, "frame-every": np.int64(frame_every), "seed": np.int64(seed),
                          "packing_fraction": packing_fraction, "mean_radius": float(radius.mean()),
                          "mean_mass": float(mass.mean()), "dt": dt, "grains": np.int64(grains),
                          "program": "gf-shear"})
        obs = f.create_group("observables")
        for name, value in (("strain", times * rate), ("pressure", p), ("shear_stress", s),
                            ("normal_stress_difference", np.full(n, n1)), ("temperature", temp),
                            ("stress_kinetic", _tensor(pk, s * pk / p, n1)),
                            ("stress_static", _tensor(ps, s * ps / p, n1)),
                            ("stress_collisional", _tensor(0.9 * ps, 0.9 * s * ps / p, n1)),
                            ("contacts", np.full(n, grains, dtype=np.int64)),
                            ("solver_iterations", np.full(n, 10, dtype=np.int64)),
                            ("solver_residual", np.full(n, 1e-12)), ("max_overlap", np.full(n, 1e-10))):
            _element(obs, name, value, steps, times)
        frames = np.concatenate(([0], steps[frame_every - 1::frame_every]))
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
    """The parts of a gf-pack packing that report.py reads."""
    with h5py.File(path, "w") as f:
        f.create_group("parameters").attrs.update({"packing-fraction": packing_fraction, "mean-diameter": 1.4,
                                                   "seed": np.int64(seed)})
        f.create_dataset("particles/grains/radius", data=np.full(grains, 0.7))
        obs = f.create_group("observables")
        for name, value in (("packing_fraction", packing_fraction), ("max_overlap", 1e-10), ("wall_seconds", 0.1)):
            _element(obs, name, np.array([value]), [0], [0.0])
    return path
