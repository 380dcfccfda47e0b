"""Seed 003 (Hammami 2015) Figs 4.12-4.13: the test-carrier spectrum's largest line near f_m
is "right on f_m" (65 f_c). Sequential phasing (Table 4.2) of three identical, equally spaced
planets cancels the net mesh torque on the carrier at h·f_m unless h·Z_s and h·Z_r are
multiples of N (Parker 2000), so f_m (h = 1) can appear only through an asymmetry. Here: the
carrier's amplitude at orders 62-68 and 130, 195 (12-DOF bench, 100 N·m, 1498.5 rpm, square
meshes with the load law, planet-pass force), symmetric vs the thesis's ch. 5 pin-hole errors
(60/10/-60 µm, tangential) vs carrier gravity, in both readings of the test-ring support.
Run: PYTHONPATH=src python experiments/seed003_carrier_fm.py
"""
from __future__ import annotations

import sys

import numpy as np

sys.path.insert(0, ".")
sys.path.insert(0, "experiments")
from seed003_load_sweep import DT, FC, TC, config  # noqa: E402
from tests.validation.seed003._bench import run  # noqa: E402

ORDERS = np.array([62, 63, 64, 65, 66, 67, 68, 130, 195])


def exact_orders(x, orders):
    t = np.arange(x.size) * DT
    return np.array([abs(2 * np.mean(x * np.exp(-2j * np.pi * k * FC * t))) for k in orders])


def carrier_orders(ds, dof="test.carrier.u"):
    sel = ds.sel(time=slice(0.1, None))
    n = int(round(3 * TC / DT))
    acc = np.gradient(sel.v.sel(dof=dof).values, DT)[:n]
    return exact_orders(acc - acc.mean(), ORDERS)


if __name__ == "__main__":
    np.set_printoptions(precision=3, suppress=False, linewidth=150)
    print("orders", ORDERS)
    for unit in ("Nm/rad", "N/m"):
        for name, kw in (("symmetric", {}), ("pin errors 60/10/-60 µm",
                                             {"pin_errors": [60e-6, 10e-6, -60e-6]})):
            d = config(100.0, unit=unit, **kw)
            a = carrier_orders(run(d, 0.1 + 3 * TC, DT)[2])
            print(f"{unit:7s} {name:24s} largest near f_m: order {ORDERS[:7][np.argmax(a[:7])]}"
                  f"  amp {a}")


def config36(torque, pin_errors=None, tip_relief=5e-6):
    from tests.validation.seed003._bench import raw, square_meshes, stationary
    d = square_meshes(stationary(raw("planetary_bench_36dof.toml"), 1498.5, torque), 1.5,
                      {"tip_relief_m": tip_relief})
    st = d["planetary_dynamics"]["stages"][1]
    st["planet_pass"] = {}
    if pin_errors:
        st["pin_errors_m"] = pin_errors
    d["planetary_dynamics"]["simulation"]["modal_damping_ratio"] = 0.02
    return d


def main36():
    for name, kw in (("symmetric", {}), ("pin errors", {"pin_errors": [60e-6, 10e-6, -60e-6]})):
        a = carrier_orders(run(config36(100.0, **kw), 0.1 + 3 * TC, DT)[2])
        print(f"36-DOF {name:12s} largest near f_m: order {ORDERS[:7][np.argmax(a[:7])]}"
              f"  amp {a}", flush=True)
