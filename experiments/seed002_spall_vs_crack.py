"""Seed 002 (Thibault et al. 2024) Fig 18: why is our spall's IAS perturbation ≈ 10× the deep
crack's? Quasi-static answer from the PE mesh stiffness of the low stage (55-tooth wheel):
k(θ) over the hunting period with each fault of tests/validation/seed002/_runs.py, the static
transmission error change ΔSTE = F/k_fault − F/k_healthy (F: 100 N·m on the output), its peak,
its area (mesh cycles × m) and its duration; and how the spall's radial width (a third of the
whole tooth height, 2.9 mm, or of the active profile) sets the duration, not the depth.
Run: PYTHONPATH=src python experiments/seed002_spall_vs_crack.py
"""
from __future__ import annotations

import sys

sys.path.insert(0, ".")
from tests.validation.seed002._runs import _variant  # noqa: E402

from geardyn.config.gears import pair_model  # noqa: E402
from geardyn.config.loader import parse_config  # noqa: E402
from geardyn.gears.pe_stiffness import mesh_stiffness  # noqa: E402

NPC = 64


def table(case: str, spall_width: float | None = None):
    d = _variant(case)
    if spall_width is not None:
        low = next(g for g in d["gear_geometry"] if g["pair"] == "low")
        low["spalls"][0]["radial_width_m"] = spall_width
    pm = pair_model(parse_config(d), "low")
    g = pm.geometry
    return g, mesh_stiffness(g, n_per_cycle=NPC, n_cycles=None, faults=pm.faults)


def main() -> None:
    g, h = table("healthy")
    rb = g.base_radius[1]
    f = 100.0 / rb  # N along the line of action (100 N·m on the output wheel)
    print(f"low stage: z {g.a.teeth}/{g.b.teeth}, base pitch {g.base_pitch * 1e3:.3f} mm, "
          f"F = {f:.0f} N, k mean {h.total.mean():.3e} N/m, "
          f"STE mean {f / h.total.mean() * 1e6:.2f} µm")
    rows = [("crack15", None), ("crack25", None), ("gear_spall", None),
            ("gear_spall", 0.0029 / 2), ("gear_spall", 0.0029 / 4)]
    for case, w in rows:
        _, t = table(case, w)
        loss = 1 - t.total / h.total
        dste = f / t.total - f / h.total
        on = dste > 0.02 * dste.max()
        print(f"{case:10s} width {'' if w is None else f'{w * 1e3:.2f} mm':>8s}: "
              f"max stiffness loss {loss.max():6.1%}, ΔSTE peak {dste.max() * 1e6:6.3f} µm, "
              f"area {dste.sum() / NPC * 1e6:7.4f} µm·cycle, duration {on.sum() / NPC:4.2f} "
              "mesh cycles")


if __name__ == "__main__":
    main()
