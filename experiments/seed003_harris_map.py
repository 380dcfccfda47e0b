"""Seed 003 (Hammami 2015) load sweep, Figs 4.16-4.17: does the tip relief's displacement
excitation (the loaded static transmission error, STE) make the test-ring vibration FALL with
load, as the thesis's does, where our parametric square mesh makes it grow?

Harris map (Harris 1958; Munro 1962): with tip relief C_a, the loaded STE peak-to-peak of a
spur pair falls from no load to the "design load" (single-pair deflection ≈ C_a), then rises.
For a linear relief from each tip down to the highest/lowest point of single contact ("long
relief", roll length (ε−1)p_b) and a constant pair stiffness k_p, the double-contact STE is
(C_a + F/k_p)/2 and the single-contact STE F/k_p, so STE p-p = |C_a − F/k_p|/2 (C_a/2 at no
load, 0 at F/k_p = C_a). A relief no longer than half the double-contact zone ("short", roll
≤ (ε−1)p_b/2) leaves an unrelieved double-contact stretch where STE = F/2k_p beside the
single-contact F/k_p: p-p ≈ F/2k_p, growing with load from 0.

Bench pairs (Table 3.1 has no tooth geometry; this one reproduces its base diameters and means):
- tool 20°, module m = d_b,s/(z_s cos 20°) = 4.0825 mm (Table 3.1 base diameters 61.38, 92.08,
  249.38 mm → d_b/z = 3.836 mm), face width b = 30 mm (Henriot, Hammami 2015 eq 1.14, with
  k̄_sp = 4.46e8 N/m and z = 16/24: b = 446/14.77 = 30.2 mm);
- sun–planet: x_s = +0.1, x_p = −0.1 → centre distance 81.65 mm and working pressure angle
  20.0° (the bench examples' r_c and α_s); ε_α = 1.542;
- planet–ring (internal, geardyn builds it at the reference centre distance, x_r = x_p): ring
  addendum 0.8 m (1.0 m puts the ring tip below the planet's form circle), working angle 20°
  (the 12-DOF model's α_r = 15.59° would need a shift sum geardyn's internal pairs do not take);
  ε_α = 1.748;
- geardyn's PE mean stiffness of these pairs (steel, `mean_stiffness`): 4.50e8 and 6.34e8 N/m,
  Table 3.1 4.46e8 and 6.28e8 (+0.9 %, +1.0 %).

Load path (notes §4.5, `test_load_sweep.test_law_closed_form`): ring torque T on the free
reaction ring, mesh force per planet F = T/(3 r_br), r_br = 124.69 mm, on both the sun and the
ring mesh (planet torque balance); the solver takes the torque F·r_b,a on the pinion.
Reliefs: linear (in radius, `TipRelief`) on both tips of each pair, depth C_a = 5, 10, 20 µm,
roll length ρ p_b from each tip: ρ = 0.25 (the load law's `relief_roll_ratio`, a short relief
here) and ρ = ε − 1 (long relief, to the single-contact points).

Dynamic check (`bench`): the 12-DOF bench of `seed003_load_sweep.py` with each mesh replaced by
the pair's loaded mesh linearised at the run's static force F: k(ξ) the tangent stiffness
dF/dδ (solver at F(1 ± 2 %)), e(ξ) = STE(ξ) − F/k(ξ) the equivalent displacement error
(Velex & Maatar 1996: mesh force k(t)(δ − e(t))), so the static mesh deflection is the loaded
STE. 64 samples per mesh cycle, ξ = 0 a tooth entry (as the square wave's X = 0). Both sets'
meshes are replaced (the experiment wraps `build.mesh_laws`; no library change). Three equally
spaced, sequentially phased planets cancel the mesh excitation on the ring rotation at f_m and
2f_m (65 is no multiple of 3), so on the test ring those lines come from the planet-pass force
alone (eq 4.13): its mesh term is set to the linearised law's blocked ring-mesh force
k(ξ)(x̄ − e(ξ)) (x̄ the mean approach), which for e = 0 is the model's own k(X)·δ̄.

Run: PYTHONPATH=src:experiments python experiments/seed003_harris_map.py [harris] [bench]
"""

from __future__ import annotations

import math
import sys
from unittest import mock

import numpy as np

from geardyn.gears import Corrections, GearBlank, TipRelief, mesh_geometry, square_wave
from geardyn.gears import static_transmission_error as ste_solve
from geardyn.gears.pe_stiffness import mean_stiffness
from geardyn.models.planetary.build import mesh_harmonics
from geardyn.models.planetary.dynamics import MeshLaw
from geardyn.models.planetary.loads import loaded_square_mesh

R_BS, R_BR = 0.03069, 0.12469
ALPHA = math.radians(20.0)
MODULE = 2 * R_BS / (16 * math.cos(ALPHA))
FACE = 0.030
TORQUES = (1.0, 100.0, 300.0, 500.0, 700.0, 900.0)  # ring torque (N·m); 1 N·m stands for 0+
RELIEFS = (5e-6, 10e-6, 20e-6)


def pairs():
    """(sun–planet, planet–ring) MeshGeometry of the bench (module docstring)."""
    sun = mesh_geometry(
        GearBlank(16, profile_shift=0.1),
        GearBlank(24, profile_shift=-0.1),
        MODULE,
        ALPHA,
        FACE,
        label="sun-planet",
    )
    ring = mesh_geometry(
        GearBlank(24, profile_shift=-0.1),
        GearBlank(65, internal=True, profile_shift=-0.1, addendum_coef=0.8),
        MODULE,
        ALPHA,
        FACE,
        label="planet-ring",
    )
    return sun, ring


def reliefs(g, depth: float, roll: float) -> Corrections:
    """Linear tip relief of ``depth`` (m) on both tips, starting ``roll`` base pitches of roll
    length from each tip (an internal gear's tip is its smallest radius: start above it)."""
    rho = [math.sqrt(g.tip_radius[i] ** 2 - g.base_radius[i] ** 2) for i in (0, 1)]
    span = roll * g.base_pitch
    r_a = math.hypot(g.base_radius[0], rho[0] - span)
    r_b = math.hypot(g.base_radius[1], rho[1] + span if g.internal else rho[1] - span)
    return Corrections((TipRelief("a", depth, r_a), TipRelief("b", depth, r_b)))


def mesh_force(ring_torque: float) -> float:
    """Mesh force per planet (N), sun and ring meshes alike: T/(3 r_br)."""
    return ring_torque / (3 * R_BR)


def ste(g, force: float, depth: float, roll: float, n: int = 128) -> np.ndarray:
    """Loaded STE (m) over one mesh cycle, n samples, at line-of-action force ``force`` (N)."""
    corr = reliefs(g, depth, roll) if depth > 0 else None
    return ste_solve(g, force * g.base_radius[0], n_per_cycle=n, corrections=corr).ste


def harmonics(x: np.ndarray, h: int = 3) -> np.ndarray:
    """Amplitudes of mesh orders 1..h of a one-cycle table."""
    return np.abs(np.fft.rfft(x))[1 : h + 1] * 2 / x.size


def harris_table(g, roll: float, depth: float) -> list[tuple[float, ...]]:
    """Rows (T, F, δ̄/C_a, STE p-p, h1, h2, h3) in N·m, N, -, µm; δ̄ = F/k̄ (load-law δ)."""
    kbar = mean_stiffness(g)
    rows = []
    for t in TORQUES:
        f = mesh_force(t)
        s = ste(g, f, depth, roll)
        rows.append((t, f, f / kbar / depth, np.ptp(s) * 1e6, *(harmonics(s) * 1e6)))
    return rows


def square_ste_pp(force: float, which: str, depth: float) -> float:
    """STE p-p (µm) of our current loaded square mesh (load law, k_max/k_min = 1.2/0.8 k̄₀,
    c₀ = 1.5, ρ = 0.25): F/k_min − F/k_max while c < 2 (`loaded_square_mesh`)."""
    k0 = 4.46e8 if which == "sun" else 6.28e8
    kx, kn, c = loaded_square_mesh(1.2 * k0, 0.8 * k0, 1.5, force, depth)
    return 0.0 if c >= 2 else force * (1 / kn - 1 / kx) * 1e6


def linearised_law(g, force: float, depth: float, roll: float, n: int = 64):
    """(k, e) tables of the pair's loaded mesh linearised at ``force``: tangent stiffness
    (N/m) and equivalent error e = STE − F/k (m), so that k(STE − e) = F."""
    lo, mid, hi = (ste(g, force * s, depth, roll, n) for s in (0.98, 1.0, 1.02))
    k = 0.04 * force / (hi - lo)
    return k, mid - force / k


def _signs(cfg) -> dict[tuple[str, str], float]:
    """Sign of each stage's sun/ring mesh force under the run's static load (the gap of the
    relief must reduce the compression, whichever way the mesh is loaded)."""
    from geardyn.models.planetary.build import _udof, model_from_config
    from geardyn.models.planetary.dynamics import spring_forces, static_solve

    model = model_from_config(cfg)
    sim = cfg.planetary_dynamics.simulation
    loads = {_udof(model, t.body): t.torque_nm / model.body(t.body).radius for t in sim.torques}
    q = static_solve(model, loads, [_udof(model, sc.body) for sc in sim.speed_controls])
    fs = spring_forces(model, q)
    out = {}
    for s in model.springs:
        if s.kind in ("mesh_sun", "mesh_ring"):
            out[(s.stage, s.kind[5:])] = float(np.sign(fs[s.name]))
    return out


def blocked_force_harmonics(k: np.ndarray, e: np.ndarray, force: float, h: int = 3) -> np.ndarray:
    """Relative harmonics (of F) of the mesh force with the gears held at the mean approach
    x̄ (blocked force k(ξ)(x̄ − e(ξ)), mean F): the planet-pass force's mesh term. For e = 0 it
    is the quasi-static k(ξ)·δ̄ the model's planet-pass force uses (``mesh_harmonics``)."""
    xbar = (force + np.mean(k * e)) / np.mean(k)
    return harmonics(k * (xbar - e), h) / force


def bench(
    torque: float, depth: float = 10e-6, roll: float | None = None, law: str = "ste"
) -> tuple[float, float, float, float]:
    """Test-ring (RMS, RMS below 1.1 kHz, f_m group, 2f_m group) acceleration (m/s²; groups:
    Hann-spectrum peak within ±25 Hz, as ``seed003_load_sweep``) of the 12-DOF bench at ring
    torque ``torque`` (planet-pass force on, as in ``seed003_load_sweep``); ``law`` "ste":
    linearised loaded meshes of the pairs (``roll`` None = long relief ε − 1) and the
    planet-pass mesh term from their blocked ring-mesh force; "square": the current load-law
    square meshes (C_a = ``depth``)."""
    from seed003_load_sweep import DT, TC, config

    from geardyn.config.loader import parse_config
    from geardyn.models.planetary import build
    from geardyn.models.planetary.dynamics import simulate

    d = config(torque, tip_relief=depth)
    if law == "square":
        p = build.prepare(parse_config(d), t_end_s=0.1 + 3 * TC)
    else:
        f = mesh_force(torque)
        sg, rg = pairs()
        tables = {
            w: linearised_law(g, f, depth, g.contact_ratio - 1 if roll is None else roll)
            for w, g in (("sun", sg), ("ring", rg))
        }
        rel = blocked_force_harmonics(*tables["ring"], f)
        d["planetary_dynamics"]["stages"][1]["planet_pass"] = {"harmonics": list(rel)}
        cfg = parse_config(d)
        sign = _signs(cfg)
        original = build.mesh_laws

        def laws(cfg_, model, mesh_force_n=None):
            out = original(cfg_, model, mesh_force_n)
            for stage, which in list(out):
                k, e = tables[which]
                out[(stage, which)] = MeshLaw(k, e=-sign[(stage, which)] * e)
            return out

        with mock.patch.object(build, "mesh_laws", laws):
            p = build.prepare(cfg, t_end_s=0.1 + 3 * TC)
    ds = simulate(p.model, p.system, p.mesh_index, p.q0, p.v0, 0.1 + 3 * TC, DT)
    assert ds.attrs["status"] == "ok", ds.attrs["diagnosis"]
    return ring_numbers(ds, DT)


def ring_numbers(
    ds, dt: float, t0: float = 0.1, band_hz: float = 1100.0
) -> tuple[float, float, float, float]:
    """(RMS, RMS of the part below ``band_hz``, f_m group, 2f_m group) of the test-ring
    acceleration (m/s² on u = r θ) after ``t0``."""
    from seed003_load_sweep import FM

    sel = ds.sel(time=slice(t0, None))
    acc = np.gradient(sel.v.sel(dof="test.ring.u").values, dt)
    acc = acc - acc.mean()
    f = np.fft.rfftfreq(acc.size, dt)
    spec = np.fft.rfft(acc)
    low = np.fft.irfft(np.where(f < band_hz, spec, 0), acc.size)
    w = np.hanning(acc.size)
    a = np.abs(np.fft.rfft(acc * w)) * 2 / w.sum()
    a1 = a[(f > FM - 25) & (f < FM + 25)].max()
    a2 = a[(f > 2 * FM - 25) & (f < 2 * FM + 25)].max()
    return (float(np.sqrt(np.mean(acc**2))), float(np.sqrt(np.mean(low**2))), float(a1), float(a2))


def main_harris() -> None:
    sun, ring = pairs()
    for g in (sun, ring):
        print(
            f"{g.label}: eps {g.contact_ratio:.3f}, k̄ {mean_stiffness(g):.3e} N/m, "
            f"p_b {g.base_pitch * 1e3:.3f} mm"
        )
        for roll in (0.25, g.contact_ratio - 1):
            for depth in RELIEFS:
                print(
                    f"  relief ρ {roll:.3f} p_b, C_a {depth * 1e6:g} µm:"
                    "  T, F, δ̄/C_a, STE p-p, h1, h2, h3 (µm)"
                )
                for r in harris_table(g, roll, depth):
                    print("    {:5g} {:7.1f} {:6.3f} {:7.3f} {:7.3f} {:7.3f} {:7.3f}".format(*r))
        which = "sun" if g is sun else "ring"
        for depth in RELIEFS:
            pp = [square_ste_pp(mesh_force(t), which, depth) for t in TORQUES[1:]]
            print(f"  current square law, C_a {depth * 1e6:g} µm: STE p-p {np.round(pp, 3)}")
    print("blocked ring-mesh force, harmonics 1, 2 (N) at 100..900 N·m:")
    for name, depth, roll in (
        ("long C_a 5", 5e-6, None),
        ("long C_a 10", 10e-6, None),
        ("long C_a 20", 20e-6, None),
        ("short C_a 10", 10e-6, 0.25),
    ):
        rows = []
        for t in TORQUES[1:]:
            f = mesh_force(t)
            k, e = linearised_law(ring, f, depth, ring.contact_ratio - 1 if roll is None else roll)
            rows.append(blocked_force_harmonics(k, e, f, 2) * f)
        h = np.round(np.array(rows), 0)
        print(f"  {name}: h1 {h[:, 0]}  h2 {h[:, 1]}")
    rows = []
    for t in TORQUES[1:]:
        f = mesh_force(t)
        kx, kn, c = loaded_square_mesh(1.2 * 6.28e8, 0.8 * 6.28e8, 1.5, f, 10e-6)
        rows.append(mesh_harmonics(MeshLaw(square_wave(np.arange(64) / 64, kx, kn, c)), 2)[0] * f)
    print(
        f"  current square law C_a 10: h1 {np.round(np.array(rows)[:, 0], 0)}  "
        f"h2 {np.round(np.array(rows)[:, 1], 0)}"
    )


def main_bench() -> None:
    cases = {
        "square law C_a 10 (current)": dict(law="square"),
        "STE long relief C_a 10": dict(),
        "STE short relief (ρ 0.25) C_a 10": dict(roll=0.25),
        "STE long relief C_a 5": dict(depth=5e-6),
        "STE long relief C_a 20": dict(depth=20e-6),
    }
    for name, kw in cases.items():
        rows = np.array([bench(t, **kw) for t in TORQUES[1:]])
        rms, low, a1, a2 = rows.T
        print(
            f"{name}:\n  rms {np.round(rms, 2)}\n  rms < 1.1 kHz {np.round(low, 2)}\n"
            f"  f_m {np.round(a1, 2)}\n  2f_m {np.round(a2, 2)}",
            flush=True,
        )


if __name__ == "__main__":
    np.set_printoptions(linewidth=150)
    what = sys.argv[1:] or ["harris", "bench"]
    if "harris" in what:
        main_harris()
    if "bench" in what:
        main_bench()
